#include "transport/file_output.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>

#include "transport/posix/errors.hpp"

namespace gpsemu::transport {

namespace {

constexpr int kFlushWaitMs = 1000;  ///< one wait for a slow reader in flush() (milliseconds)
constexpr int kFlushWaits = 5;      ///< how many such waits before flush() gives up

/// Opens `path` for writing as `mode` says without changing what it holds; `created` receives
/// the file this made (none when it existed). Returns -1 with errno set when it cannot.
int open_unchanged(const std::filesystem::path& path, FileMode mode, std::filesystem::path& created) {
  const int flags = O_WRONLY | O_CLOEXEC | O_NOCTTY | (mode == FileMode::append ? O_APPEND : 0);
  int fd = ::open(path.c_str(), flags | O_CREAT | O_EXCL, 0644);
  if (fd >= 0) {
    created = path;
    return fd;
  }
  if (errno != EEXIST || mode == FileMode::create_new) return -1;
  fd = ::open(path.c_str(), flags);
  if (fd >= 0 || errno != ENOENT) return fd;
  // A dangling symlink (O_EXCL does not follow it; without O_EXCL its target is created), or a
  // file removed meanwhile: what was created is whatever the descriptor names.
  fd = ::open(path.c_str(), flags | O_CREAT, 0644);
  if (fd >= 0) {
    std::error_code ec;
    created = std::filesystem::read_symlink("/proc/self/fd/" + std::to_string(fd), ec);
  }
  return fd;
}

}  // namespace

FileOutput::FileOutput(int fd, bool owns_fd, std::string description, bool flush_each_epoch)
    : fd_(fd),
      owns_fd_(owns_fd),
      description_(std::move(description)),
      flush_each_epoch_(flush_each_epoch) {
  pending_.reserve(kBufferBytes);
  epoch_ends_.reserve(1024);
  count_when_sent();
}

FileOutput::FileOutput(const std::filesystem::path& path, bool flush_each_epoch, FileMode mode)
    : FileOutput(-1, true, "file " + path.string(), flush_each_epoch) {
  mode_ = mode;
  fd_ = open_unchanged(path, mode, created_);
  if (fd_ >= 0) return;
  if (errno == EEXIST) {
    throw std::runtime_error(fmt::format(
        "file output: {} already exists and file:PATH?mode=new refuses to overwrite it (remove it, or use "
        "file:{}?mode=append to add to it, or file:{} to replace it)", path.string(), path.string(), path.string()));
  }
  throw std::runtime_error(fmt::format("file output: cannot open {} for writing: {}", path.string(),
                                       posix::errno_text(errno)));
}

std::unique_ptr<FileOutput> FileOutput::to_stdout(bool flush_each_epoch) {
  if (::fcntl(STDOUT_FILENO, F_GETFL) < 0) {
    throw std::runtime_error(
        fmt::format("stdout output: standard output is not open: {}", posix::errno_text(errno)));
  }
  return std::unique_ptr<FileOutput>(
      new FileOutput(STDOUT_FILENO, false, "stdout", flush_each_epoch));
}

FileOutput::~FileOutput() {
  flush();
  if (owns_fd_ && fd_ >= 0 && ::close(fd_) != 0) {
    spdlog::warn("{}: close failed: {}", description_, posix::errno_text(errno));
  }
  // Start-up failed before the run began: a file that was not there is not left behind.
  if (!committed_ && !created_.empty()) ::unlink(created_.c_str());
}

bool FileOutput::take_over(std::string& error_text) {
  committed_ = true;
  if (mode_ != FileMode::truncate || !created_.empty() || fd_ < 0) return true;
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) return true;  // a device or FIFO: nothing to truncate
  if (::ftruncate(fd_, 0) == 0) return true;
  error_text = fmt::format("cannot truncate: {}", posix::errno_text(errno));
  return false;
}

void FileOutput::commit() {
  if (committed_) return;
  std::string error_text;
  if (!take_over(error_text)) throw std::runtime_error(fmt::format("{}: {}", description_, error_text));
}

FileOutput::DrainResult FileOutput::drain(bool wait, std::string& error_text) {
  std::size_t done = 0;
  int waits = 0;
  DrainResult result = DrainResult::done;
  while (done < pending_.size()) {
    const ssize_t n = ::write(fd_, pending_.data() + done, pending_.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      // Standard output may be a non-blocking pipe whose reader is slow.
      pollfd pfd{fd_, POLLOUT, 0};
      if (wait && waits++ < kFlushWaits && ::poll(&pfd, 1, kFlushWaitMs) >= 0) continue;
      result = DrainResult::would_block;
      break;
    }
    // A failed file (disk full, I/O error, reader gone) loses what was buffered: keeping it
    // would only make every later epoch fail too.
    if (n < 0 && errno == EPIPE) gone_ = true;
    error_text = fmt::format("write failed: {}; {} buffered bytes lost",
                             n < 0 ? posix::errno_text(errno) : "no progress", pending_.size() - done);
    sent(done);
    const std::uint64_t lost = epoch_ends_.size();
    pending_.clear();
    epoch_ends_.clear();
    count_lost(lost, error_text);
    return DrainResult::failed;
  }
  sent(done);
  pending_.erase(0, done);
  return result;
}

void FileOutput::sent(std::size_t bytes) {
  if (bytes == 0) return;
  // The epochs whose last byte the operating system took are written; a partial one is not yet.
  const auto complete = std::upper_bound(epoch_ends_.begin(), epoch_ends_.end(), bytes) - epoch_ends_.begin();
  count_sent(static_cast<std::uint64_t>(complete), bytes);
  epoch_ends_.erase(epoch_ends_.begin(), epoch_ends_.begin() + complete);
  for (auto& end : epoch_ends_) end -= bytes;
}

WriteStatus FileOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  if (gone_) {
    error_text = "the reader closed the pipe";
    return WriteStatus::error;
  }
  if (!committed_ && !take_over(error_text)) return WriteStatus::error;
  if (!pending_.empty() && pending_.size() + bytes.size() > kBufferBytes) {
    // A failure here is counted for the buffered epochs it lost; this epoch is not written either.
    if (drain(false, error_text) == DrainResult::failed) return WriteStatus::error;
    if (!pending_.empty() && pending_.size() + bytes.size() > kBufferBytes) {
      error_text = fmt::format("the reader is not keeping up ({} bytes waiting)", pending_.size());
      return WriteStatus::dropped;
    }
  }
  pending_.append(bytes);
  epoch_ends_.push_back(pending_.size());
  // A failure in drain() counted this epoch among the lost ones.
  if (flush_each_epoch_) (void)drain(false, error_text);
  return WriteStatus::ok;
}

void FileOutput::flush() {
  if (pending_.empty()) return;
  std::string error_text;
  switch (drain(true, error_text)) {
    case DrainResult::done:
      break;
    case DrainResult::would_block:
      spdlog::warn("{}: reader not keeping up; {} bytes not written at flush", description_,
                   pending_.size());
      break;
    case DrainResult::failed:  // counted and reported by drain()
      break;
  }
}

}  // namespace gpsemu::transport
