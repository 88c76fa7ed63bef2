#include "transport/pty_output.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "transport/posix/errors.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::transport {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void throw_errno(const std::string& what) {
  throw std::runtime_error(fmt::format("pty output: {}: {}", what, posix::errno_text(errno)));
}


/// The byte of a pty that a gpsemu serving `link` locks on its own slave descriptor (an open file
/// description lock: any process can test it, and it goes with its holder however that ends).
/// The byte is picked by the link's absolute path (FNV-1a), so a pty number reused by another
/// gpsemu for another link does not count.
struct flock link_marker(const fs::path& link, short type) {
  std::error_code ec;
  const fs::path absolute = fs::absolute(link, ec);
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const unsigned char c : (ec ? link : absolute).lexically_normal().string()) hash = (hash ^ c) * 0x100000001b3ULL;
  struct flock lock {};
  lock.l_type = type;
  lock.l_whence = SEEK_SET;
  lock.l_start = static_cast<off_t>((std::uint64_t{1} << 40) + (hash & 0xffffffffULL));
  lock.l_len = 1;
  return lock;
}

/// Whether the pty `target` (an existing link's target) is held by a running gpsemu serving
/// `link`. Only /dev/pts/N is probed: opening a serial line could toggle its modem lines.
bool served_by_running_gpsemu(const fs::path& link, const fs::path& target) {
  if (target.string().rfind("/dev/pts/", 0) != 0) return false;
  const posix::UniqueFd fd(::open(target.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC));
  if (!fd.valid()) return false;  // not ours to open: not a gpsemu of this user
  struct flock lock = link_marker(link, F_WRLCK);
  return ::fcntl(fd.get(), F_OFD_GETLK, &lock) == 0 && lock.l_type != F_UNLCK;
}

}  // namespace

PtyOutput::PtyOutput(std::optional<fs::path> link) : link_(std::move(link)) {
  try {
    open_pty();
    if (link_) create_link();
  } catch (...) {
    close_fds();
    throw;
  }
  spdlog::info("pty output: {}", describe());
}

PtyOutput::~PtyOutput() {
  if (link_) {
    // Only remove what is still ours: another run may have replaced the link meanwhile.
    std::error_code ec;
    const fs::path target = fs::read_symlink(*link_, ec);
    if (!ec && target == device_path_) fs::remove(*link_, ec);
  }
  close_fds();
}

void PtyOutput::open_pty() {
  master_fd_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master_fd_ < 0) throw_errno("cannot open a pseudo-terminal (posix_openpt)");
  if (::grantpt(master_fd_) != 0) throw_errno("grantpt failed");
  if (::unlockpt(master_fd_) != 0) throw_errno("unlockpt failed");
  std::array<char, 128> name{};
  if (::ptsname_r(master_fd_, name.data(), name.size()) != 0) throw_errno("ptsname failed");
  device_path_ = name.data();

  // Our own slave descriptor: while it is open, a client closing the device never hangs up the
  // pty (no EIO/HUP on the master), and we can see and flush what no client has read.
  slave_fd_ = ::open(name.data(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave_fd_ < 0) throw_errno("cannot open " + device_path_.string());
  termios tio{};
  if (::tcgetattr(slave_fd_, &tio) != 0) throw_errno("tcgetattr on " + device_path_.string());
  ::cfmakeraw(&tio);
  if (::tcsetattr(slave_fd_, TCSANOW, &tio) != 0) {
    throw_errno("cannot set raw mode on " + device_path_.string());
  }

  const int flags = ::fcntl(master_fd_, F_GETFL);
  if (flags < 0 || ::fcntl(master_fd_, F_SETFL, flags | O_NONBLOCK) != 0) {
    throw_errno("cannot make the pty master non-blocking");
  }
}

void PtyOutput::create_link() {
  const fs::path& link = *link_;
  if (link.empty() || !link.has_filename()) {
    throw std::runtime_error(fmt::format("pty output: invalid symlink path '{}'", link.string()));
  }
  std::error_code ec;
  const fs::path dir = link.has_parent_path() ? link.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) {
    throw std::runtime_error(
        fmt::format("pty output: cannot create symlink {}: directory {} does not exist",
                    link.string(), dir.string()));
  }
  const fs::file_status status = fs::symlink_status(link, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    throw std::runtime_error(
        fmt::format("pty output: cannot inspect {}: {}", link.string(), ec.message()));
  }
  if (fs::exists(status)) {
    if (!fs::is_symlink(status)) {
      throw std::runtime_error(fmt::format(
          "pty output: {} exists and is not a symlink; refusing to replace it (remove it or "
          "choose another link path)",
          link.string()));
    }
    const fs::path old_target = fs::read_symlink(link, ec);
    if (!old_target.empty() && served_by_running_gpsemu(link, old_target)) {
      throw std::runtime_error(fmt::format(
          "pty output: {} -> {} is the link of another gpsemu that is still running (it holds that pty); "
          "refusing to take it over: stop that gpsemu or choose another link path", link.string(),
          old_target.string()));
    }
    if (!fs::remove(link, ec) || ec) {
      throw std::runtime_error(fmt::format("pty output: cannot remove old symlink {}: {}",
                                           link.string(), ec.message()));
    }
    if (!old_target.empty() && old_target != device_path_ && fs::exists(old_target, ec)) {
      spdlog::warn("pty output: replaced symlink {} -> {} (its target still exists, but no running gpsemu "
                   "serves it through this link)",
                   link.string(), old_target.string());
    } else {
      spdlog::info("pty output: replaced stale symlink {} -> {} left by an earlier run",
                   link.string(), old_target.string());
    }
  }
  // Marks this pty as serving `link` before the link exists, for a second gpsemu to find.
  struct flock marker = link_marker(link, F_WRLCK);
  if (::fcntl(slave_fd_, F_OFD_SETLK, &marker) != 0) {
    spdlog::warn("pty output: cannot lock {} for {}: {} (a second gpsemu could take the link over)",
                 device_path_.string(), link.string(), posix::errno_text(errno));
  }
  fs::create_symlink(device_path_, link, ec);
  if (ec) {
    throw std::runtime_error(fmt::format("pty output: cannot create symlink {} -> {}: {}",
                                         link.string(), device_path_.string(), ec.message()));
  }
}

void PtyOutput::close_fds() noexcept {
  if (master_fd_ >= 0) ::close(master_fd_);
  if (slave_fd_ >= 0) ::close(slave_fd_);
  master_fd_ = -1;
  slave_fd_ = -1;
}

std::string PtyOutput::describe() const {
  if (link_) return fmt::format("{} (link {})", device_path_.string(), link_->string());
  return device_path_.string();
}

void PtyOutput::discard_stale_input() {
  // Whatever is still queued on the slave side belongs to earlier epochs that no client read
  // (no client, or one that stopped reading). A client must never receive that backlog, so the
  // queue is flushed before every epoch; FIONREAD tells how much was waiting. The flush is
  // unconditional because bytes still in flight inside the kernel are not counted by FIONREAD
  // yet but would otherwise reach a late client.
  int pending = 0;
  if (::ioctl(slave_fd_, FIONREAD, &pending) != 0) pending = 0;
  ::tcflush(slave_fd_, TCIFLUSH);
  if (pending > 0) {
    ++pty_stats_.stale_epochs_discarded;
    pty_stats_.stale_bytes_discarded += static_cast<std::uint64_t>(pending);
  }
}

void PtyOutput::prepare_epoch() {
  discard_stale_input();
  report_discards();
  prepared_ = true;
}

WriteStatus PtyOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  if (!prepared_) {
    discard_stale_input();
    report_discards();
  }
  prepared_ = false;
  for (;;) {
    const ssize_t n = ::write(master_fd_, bytes.data(), bytes.size());
    if (n >= 0 && static_cast<std::size_t>(n) == bytes.size()) return WriteStatus::ok;
    if (n >= 0) {
      // The queue was empty, so this should not happen; never leave half an epoch for a client.
      ::tcflush(slave_fd_, TCIFLUSH);
      error_text = fmt::format("pty accepted only {} of {} bytes; the partial epoch was discarded",
                               n, bytes.size());
      return WriteStatus::dropped;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      error_text = "no room in the pty";
      return WriteStatus::dropped;
    }
    error_text = fmt::format("write to {} failed: {}", device_path_.string(), posix::errno_text(errno));
    return WriteStatus::error;
  }
}

void PtyOutput::service() {
  // Clients write to the receiver (gpsd probes with kilobytes of configuration strings): read it
  // without ever blocking, so the client never stalls on a full pty, and hand it to the client
  // input (the receiver's encoders; NMEA drops it).
  const posix::Drained input = posix::drain_input(master_fd_, client_input_budget,
                                                  [this](std::string_view bytes) { client_wrote(bytes); });
  pty_stats_.input_bytes_discarded += input.bytes;
  if (input.end == posix::Drained::End::failed) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_service_error_ >= std::chrono::seconds(1)) {
      spdlog::warn("{}: reading client input failed: {}", describe(), posix::errno_text(input.error));
      last_service_error_ = now;
    }
  }
  report_discards();
}

void PtyOutput::report_discards() {
  const bool changed = pty_stats_.stale_bytes_discarded != reported_.stale_bytes_discarded ||
                       pty_stats_.input_bytes_discarded != reported_.input_bytes_discarded;
  if (!changed) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_report_ < std::chrono::seconds(1)) return;
  spdlog::debug(
      "{}: discarded {} unread bytes of {} earlier epochs (no client reading) and {} bytes of "
      "client input since the last report",
      describe(), pty_stats_.stale_bytes_discarded - reported_.stale_bytes_discarded,
      pty_stats_.stale_epochs_discarded - reported_.stale_epochs_discarded,
      pty_stats_.input_bytes_discarded - reported_.input_bytes_discarded);
  reported_ = pty_stats_;
  last_report_ = now;
}

}  // namespace gpsemu::transport
