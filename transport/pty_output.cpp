#include "transport/pty_output.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "transport/posix/errors.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::transport {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void throw_errno(const std::string& what) {
  throw std::runtime_error(fmt::format("pty output: {}: {}", what, posix::errno_text(errno)));
}

/// What the line discipline of a pty holds for reading (N_TTY's buffer, less one): FIONREAD tells
/// the unread bytes exactly below it; more waits in the kernel's flip buffers, unseen.
constexpr int kLineDisciplineBytes = 4095;

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
    open_watches();
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

void PtyOutput::open_watches() {
  epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
  if (epoll_fd_ < 0) throw_errno("epoll_create1");
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = master_fd_;
  if (::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, master_fd_, &ev) != 0) throw_errno("epoll_ctl on the pty master");
  // Opened after our own slave descriptor: only clients' opens and closes count.
  opens_ = std::make_unique<posix::OpenWatch>(device_path_);
  ev.data.fd = opens_->fd();
  if (!opens_->valid() || ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, opens_->fd(), &ev) != 0) {
    spdlog::debug("pty output: cannot watch {} for clients closing it (inotify): a client's half-written frame "
                  "is not forgotten when it closes the device", device_path_.string());
  }
}

void PtyOutput::watch_room(bool on) {
  if (on == watching_room_) return;
  epoll_event ev{};
  ev.events = EPOLLIN | (on ? EPOLLOUT : 0u);
  ev.data.fd = master_fd_;
  if (::epoll_ctl(epoll_fd_, EPOLL_CTL_MOD, master_fd_, &ev) == 0) watching_room_ = on;
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
  if (epoll_fd_ >= 0) ::close(epoll_fd_);
  epoll_fd_ = -1;
  if (master_fd_ >= 0) ::close(master_fd_);
  if (slave_fd_ >= 0) ::close(slave_fd_);
  master_fd_ = -1;
  slave_fd_ = -1;
}

std::string PtyOutput::describe() const {
  if (link_) return fmt::format("{} (link {})", device_path_.string(), link_->string());
  return device_path_.string();
}

int PtyOutput::unread() const {
  int pending = 0;
  if (::ioctl(slave_fd_, FIONREAD, &pending) != 0) pending = 0;
  return pending;
}

void PtyOutput::discard_stale_input() {
  // What no client read for a whole period (no client, or one that stopped reading) is discarded,
  // so a client never receives a backlog of old epochs; what a client is reading never is. The
  // bytes read since the last check: the unread then, plus what the pty took since, less the
  // unread now (bytes still in flight inside the kernel make it look larger: never a discard).
  // Past the line discipline's buffer FIONREAD stops counting: then nobody read when the pty
  // took nothing for a period while bytes waited for room. With no client at all (inotify), or
  // when bytes went in while nobody had the device open, all of it is stale (the bytes still in
  // flight inside the kernel too, which FIONREAD does not see yet).
  notice_clients();
  send_waiting();
  // Answers alone, written since the last check, are never stale: that check may have been a
  // moment ago (an epoch with nothing to send writes nothing: a u-blox being configured, all its
  // messages off), and the client is reading them now. Nor are they when the client opened the
  // device after an epoch went in, read it and asked: what is unread is its answers. (PX4 lost
  // ACKs and MON-VER both ways, and restarted its configuration.)
  const int now_unread = unread();
  const std::uint64_t taken = taken_ - taken_at_check_;
  const std::uint64_t epoch_taken = epoch_bytes_taken_ - epoch_bytes_taken_at_check_;
  const bool aged = unread_at_check_ > 0 || epoch_taken > 0;
  const bool read_nothing = static_cast<std::uint64_t>(unread_at_check_) + taken <= static_cast<std::uint64_t>(now_unread);
  bool stale = false;
  if (nobody_open()) {
    stale = true;
  } else if (std::exchange(taken_unopened_, false)) {
    stale = taken == epoch_taken || read_nothing || now_unread >= kLineDisciplineBytes;
  } else if (now_unread > 0 || !waiting_.empty()) {
    if (now_unread < kLineDisciplineBytes && unread_at_check_ < kLineDisciplineBytes) {
      stale = aged && read_nothing;
    } else {
      stale = taken == 0 && !waiting_.empty();
    }
  }
  if (stale) discard_all(now_unread);
  unread_at_check_ = stale ? 0 : now_unread;
  taken_at_check_ = taken_;
  epoch_bytes_taken_at_check_ = epoch_bytes_taken_;
}

void PtyOutput::notice_clients() {
  // Every client closed the device: the next one to open it is a new connection, with a fresh
  // frame reader and nothing of the old one's queued for it.
  if (!opens_ || !opens_->valid() || !opens_->read_events().all_closed) return;
  discard_all(unread());
  client_left(client_);
  client_ = new_client_id();
  ++pty_stats_.clients_left;
  unread_at_check_ = 0;
  taken_at_check_ = taken_;
}

void PtyOutput::discard_all(int unread_bytes) {
  // The flush takes the kernel's flip buffers too: the pty is empty afterwards.
  ::tcflush(slave_fd_, TCIFLUSH);
  std::uint64_t bytes = static_cast<std::uint64_t>(std::max(unread_bytes, 0));
  bool any = unread_bytes > 0;
  for (const Waiting& w : waiting_) {
    bytes += w.bytes.size() - w.sent;
    if (!w.epoch && w.sent == 0) count_reply_dropped(w.bytes.size());  // whole, never begun
    any = true;
  }
  waiting_.clear();
  waiting_bytes_ = 0;
  watch_room(false);
  if (any) {
    ++pty_stats_.stale_epochs_discarded;
    pty_stats_.stale_bytes_discarded += bytes;
  }
}

void PtyOutput::prepare_epoch() {
  discard_stale_input();
  report_discards();
  prepared_ = true;
}

void PtyOutput::send_waiting() {
  while (!waiting_.empty()) {
    Waiting& w = waiting_.front();
    const ssize_t n = ::write(master_fd_, w.bytes.data() + w.sent, w.bytes.size() - w.sent);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // no room (EAGAIN), or an error the next epoch's write reports
    w.sent += static_cast<std::size_t>(n);
    taken_ += static_cast<std::uint64_t>(n);
    if (w.epoch) epoch_bytes_taken_ += static_cast<std::uint64_t>(n);
    taken_unopened_ = taken_unopened_ || nobody_open();
    waiting_bytes_ -= static_cast<std::size_t>(n);
    if (w.sent == w.bytes.size()) waiting_.pop_front();
  }
  watch_room(!waiting_.empty());
}

WriteStatus PtyOutput::send(std::string_view bytes, bool epoch, std::string& error_text) {
  send_waiting();
  std::size_t sent = 0;
  if (waiting_.empty()) {
    for (;;) {
      const ssize_t n = ::write(master_fd_, bytes.data(), bytes.size());
      if (n >= 0) {
        sent = static_cast<std::size_t>(n);
        taken_ += sent;
        if (epoch) epoch_bytes_taken_ += sent;
        taken_unopened_ = taken_unopened_ || nobody_open();
        break;
      }
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      error_text = fmt::format("write to {} failed: {}", device_path_.string(), posix::errno_text(errno));
      return WriteStatus::error;
    }
    if (sent == bytes.size()) return WriteStatus::ok;
  }
  // The rest waits behind what is queued and goes out as the client reads: never half a message
  // in the pty with something else after it.
  if (sent == 0 && waiting_bytes_ + bytes.size() > max_waiting_bytes) {
    error_text = fmt::format("no room: {} bytes wait for a client that does not read", waiting_bytes_);
    return WriteStatus::dropped;
  }
  waiting_.push_back({std::string(bytes), sent, epoch});
  waiting_bytes_ += bytes.size() - sent;
  watch_room(true);
  return WriteStatus::ok;
}

WriteStatus PtyOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  if (!prepared_) {
    discard_stale_input();
    report_discards();
  }
  prepared_ = false;
  return send(bytes, true, error_text);
}

WriteStatus PtyOutput::write_reply(ClientId client, std::string_view bytes, std::string& error_text) {
  if (client != client_) {
    error_text = "its client closed the device";
    return WriteStatus::dropped;
  }
  return send(bytes, false, error_text);
}

void PtyOutput::service() {
  // Clients write to the receiver (gpsd probes with kilobytes of configuration strings): read it
  // without ever blocking, so the client never stalls on a full pty, and hand it to the client
  // input (the receiver's encoders; NMEA drops it).
  std::uint64_t read_bytes = 0;  // taken by the receiver (a u-blox parses it); the rest is discarded
  const posix::Drained input = posix::drain_input(master_fd_, client_input_budget, [this, &read_bytes](std::string_view bytes) {
    if (client_wrote(bytes, client_)) read_bytes += bytes.size();
  });
  pty_stats_.input_bytes_discarded += input.bytes - read_bytes;
  notice_clients();  // after the input above was read: it was the old client's
  send_waiting();
  if (input.end == posix::Drained::End::failed) {
    log_limited(read_error_log_, spdlog::level::warn, "{}: reading client input failed: {}", describe(),
                posix::errno_text(input.error));
  }
  report_discards();
}

void PtyOutput::report_discards() {
  const bool changed = pty_stats_.stale_bytes_discarded != reported_.stale_bytes_discarded ||
                       pty_stats_.input_bytes_discarded != reported_.input_bytes_discarded;
  if (!changed) return;
  const std::uint64_t stale_bytes = pty_stats_.stale_bytes_discarded - reported_.stale_bytes_discarded;
  const std::uint64_t input_bytes = pty_stats_.input_bytes_discarded - reported_.input_bytes_discarded;
  std::string what;
  if (stale_bytes != 0) {
    what = fmt::format("{} unread bytes of {} earlier epochs (no client reading)", stale_bytes,
                       pty_stats_.stale_epochs_discarded - reported_.stale_epochs_discarded);
  }
  if (input_bytes != 0) {
    what += fmt::format("{}{} bytes of client input (the receiver reads none)", what.empty() ? "" : " and ", input_bytes);
  }
  if (log_limited(discard_log_, spdlog::level::debug, "{}: discarded {} since the last report", describe(), what)) {
    reported_ = pty_stats_;
  }
}

}  // namespace gpsemu::transport
