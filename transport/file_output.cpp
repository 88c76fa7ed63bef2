#include "transport/file_output.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>

#include "transport/posix/errors.hpp"

namespace gpsemu::transport {

namespace {

constexpr int kFlushWaitMs = 1000;  ///< one wait for a slow reader in flush() (milliseconds)
constexpr int kFlushWaits = 5;      ///< how many such waits before flush() gives up

}  // namespace

FileOutput::FileOutput(int fd, bool owns_fd, std::string description, bool flush_each_epoch)
    : fd_(fd),
      owns_fd_(owns_fd),
      description_(std::move(description)),
      flush_each_epoch_(flush_each_epoch) {
  pending_.reserve(kBufferBytes);
}

FileOutput::FileOutput(const std::filesystem::path& path, bool flush_each_epoch)
    : FileOutput(-1, true, "file " + path.string(), flush_each_epoch) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw std::runtime_error(fmt::format("file output: cannot open {} for writing: {}",
                                         path.string(), posix::errno_text(errno)));
  }
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
    error_text = fmt::format("write failed: {}; {} buffered bytes lost",
                             n < 0 ? posix::errno_text(errno) : "no progress", pending_.size() - done);
    pending_.clear();
    return DrainResult::failed;
  }
  pending_.erase(0, done);
  return result;
}

WriteStatus FileOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  if (!pending_.empty() && pending_.size() + bytes.size() > kBufferBytes) {
    if (drain(false, error_text) == DrainResult::failed) return WriteStatus::error;
    if (!pending_.empty() && pending_.size() + bytes.size() > kBufferBytes) {
      error_text = fmt::format("the reader is not keeping up ({} bytes waiting)", pending_.size());
      return WriteStatus::dropped;
    }
  }
  pending_.append(bytes);
  if (flush_each_epoch_ && drain(false, error_text) == DrainResult::failed) {
    return WriteStatus::error;
  }
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
    case DrainResult::failed:
      spdlog::warn("{}: {}", description_, error_text);
      break;
  }
}

}  // namespace gpsemu::transport
