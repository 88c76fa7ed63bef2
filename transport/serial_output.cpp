#include "transport/serial_output.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>

#include "transport/posix/errors.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::transport {

namespace {

constexpr int kFlushWaitMs = 1000;                         ///< flush(): longest wait for the line (ms)

speed_t speed_for(int baud_bps) {
  switch (baud_bps) {
    case 4800: return B4800;
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    default: break;
  }
  throw std::invalid_argument(fmt::format("serial output: baud {} is not supported; use one of {}", baud_bps,
                                          nmea::standard_bauds_text()));
}

int modem_bit(ModemLine line) { return line == ModemLine::rts ? TIOCM_RTS : TIOCM_DTR; }

/// Why open() failed, in words a user can act on.
std::string open_failure(int err) {
  switch (err) {
    case ENOENT:
      return "no such device (not connected? `gpsemu ports` lists serial ports)";
    case EACCES:
    case EPERM:
      return "permission denied (add the user to the group owning the device, usually 'dialout', "
             "and log in again)";
    case EBUSY:
      return "the device is in use by another program (it holds it exclusively)";
    case ENXIO:
    case ENODEV:
      return "no such device (the port exists but has no hardware behind it)";
    default:
      return posix::errno_text(err);
  }
}

}  // namespace

SerialOutput::SerialOutput(SerialTarget target, SerialOptions options, std::shared_ptr<PortLister> lister)
    : target_(std::move(target)), options_(options), lister_(std::move(lister)) {
  (void)speed_for(options_.baud_bps);  // validates the baud before anything is opened
  spec_text_ = spec_text();
  std::string path = target_.device.string();
  if (target_.usb) {
    if (!lister_) lister_ = make_system_port_lister();
    const UsbLookup found = lookup_usb_port(lister_->list_ports(), *target_.usb);
    if (!found.device) throw std::runtime_error(fmt::format("serial output {}: {}", spec_text_, found.problem));
    path = *found.device;
  }
  open_device(path);
  spdlog::info("serial output: {}", describe());
}

SerialOutput::~SerialOutput() { close_fd(true); }

void SerialOutput::close_fd(bool let_queue_drain) noexcept {
  if (fd_ < 0) return;
  // Closing a tty waits (up to 30 s) for its output queue to drain; a stalled or lost line must
  // not hold up shutdown or a reopen, so what is still queued is discarded (at shutdown after a
  // short grace for the last epoch).
  int queued = 0;
  for (int i = 0; let_queue_drain && i < 20 && ::ioctl(fd_, TIOCOUTQ, &queued) == 0 && queued > 0; ++i) {
    pollfd none{-1, 0, 0};
    (void)::poll(&none, 1, 10);
  }
  // Only a queue the driver reports is flushed: a pty reports none, and flushing it would throw
  // away the last epoch before the far end read it.
  if (::ioctl(fd_, TIOCOUTQ, &queued) == 0 && queued > 0) ::tcflush(fd_, TCOFLUSH);
  ::close(fd_);
  fd_ = -1;
}

void SerialOutput::open_device(const std::string& path) {
  const auto fail = [&](const std::string& why) {
    return std::runtime_error(fmt::format("serial output {}: cannot open {}: {}", spec_text_, path, why));
  };
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw fail(open_failure(errno));
  const auto give_up = [&](const std::string& why) {
    ::close(fd);
    return fail(why);
  };
  if (!::isatty(fd)) throw give_up("not a serial device (not a terminal)");
  // Another gpsemu (or a program using flock, like picocom) on the same line would interleave
  // sentences: refuse it; TIOCEXCL then keeps later openers (gpsd probing ports) out.
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    throw give_up(errno == EWOULDBLOCK ? "the device is in use by another program (locked)" : posix::errno_text(errno));
  }
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) throw give_up(fmt::format("tcgetattr: {}", posix::errno_text(errno)));
  ::cfmakeraw(&tio);
  tio.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | CSTOPB | CRTSCTS);
  tio.c_cflag |= CS8 | CLOCAL | CREAD;  // 8N1; ignore DCD (a PPS input must not hang us up)
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);  // no software flow control
  // VMIN 1 with O_NONBLOCK: an empty read is EAGAIN, and a read of 0 bytes means a hang-up (with
  // VMIN 0 it would return 0 whenever nothing is waiting).
  tio.c_cc[VMIN] = 1;
  tio.c_cc[VTIME] = 0;
  const speed_t speed = speed_for(options_.baud_bps);
  if (::cfsetispeed(&tio, speed) != 0 || ::cfsetospeed(&tio, speed) != 0) {
    throw give_up(fmt::format("baud {} not accepted: {}", options_.baud_bps, posix::errno_text(errno)));
  }
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) {
    throw give_up(fmt::format("cannot set {} 8N1 raw: {}", options_.baud_bps, posix::errno_text(errno)));
  }
  termios check{};
  if (::tcgetattr(fd, &check) == 0 && ::cfgetospeed(&check) != speed) {
    throw give_up(fmt::format("the driver does not accept {} baud", options_.baud_bps));
  }
  (void)::ioctl(fd, TIOCEXCL);
  ::tcflush(fd, TCIOFLUSH);  // nothing stale from before we opened it, either way
  fd_ = fd;
  device_ = path;
  char real[4096];
  if (const ssize_t n = ::readlink(path.c_str(), real, sizeof real - 1); n > 0) {
    real[n] = '\0';
    device_ = real;  // a link (pty pair, udev alias): name what it points to as well
  }
  tail_.clear();
  // Linux raises RTS and DTR on open: put back what a PPS pulse last asked for.
  std::string ignored;
  if (rts_asserted_) (void)set_modem_line(ModemLine::rts, *rts_asserted_, ignored);
  if (dtr_asserted_) (void)set_modem_line(ModemLine::dtr, *dtr_asserted_, ignored);
}

std::string SerialOutput::describe() const {
  if (fd_ < 0) return fmt::format("{} (lost: {}; looking for it)", spec_text_, lost_reason_);
  if (device_ == target_.device.string()) return spec_text_;
  return fmt::format("{} ({})", spec_text_, device_);
}

void SerialOutput::lose_device(const std::string& why) {
  lost_reason_ = why;
  close_fd(false);
  tail_.clear();
  // Whatever is on the line when it comes back is another connection: a half-read frame is dropped.
  client_left(client_);
  client_ = new_client_id();
  ++serial_stats_.device_losses;
  lost_since_ = std::chrono::steady_clock::now();
  last_attempt_ = std::chrono::steady_clock::time_point{};  // look for it again at once
  last_problem_logged_.clear();
  log_limited(loss_log_, spdlog::level::warn, "{}: device lost ({}); looking for it every {} ms to reopen it", spec_text_,
              why, options_.rescan_interval.count());
}

void SerialOutput::maybe_reopen() {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_attempt_ < options_.rescan_interval) return;
  last_attempt_ = now;
  std::string path = target_.device.string();
  std::string problem;
  if (target_.usb) {
    try {
      const UsbLookup found = lookup_usb_port(lister_->list_ports(), *target_.usb);
      if (found.device) path = *found.device;
      else problem = found.problem;
    } catch (const std::exception& e) {
      problem = e.what();
    }
  }
  if (problem.empty()) {
    try {
      open_device(path);
    } catch (const std::exception& e) {
      problem = e.what();
    }
  }
  if (problem.empty()) {
    ++serial_stats_.reopens;
    spdlog::info("{}: device back after {:.1f} s, reopened", describe(),
                 std::chrono::duration<double>(now - lost_since_).count());
    return;
  }
  // Each distinct reason is logged once; the retries themselves are not.
  if (problem != last_problem_logged_) {
    spdlog::info("{}: still looking: {}", spec_text_, problem);
    last_problem_logged_ = problem;
  }
}

bool SerialOutput::flush_tail(std::string& error_text) {
  while (!tail_.empty()) {
    const ssize_t n = ::write(fd_, tail_.data(), tail_.size());
    if (n > 0) {
      tail_.erase(0, static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n == 0 || errno == EAGAIN || errno == EWOULDBLOCK) return true;
    error_text = fmt::format("write failed: {}", posix::errno_text(errno));
    lose_device(error_text);
    return false;
  }
  return true;
}

WriteStatus SerialOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  if (fd_ < 0) maybe_reopen();
  if (fd_ < 0) {
    error_text = fmt::format("device lost ({}); looking for it", lost_reason_);
    return WriteStatus::error;
  }
  if (!tail_.empty()) {
    if (!flush_tail(error_text)) return WriteStatus::error;
    if (!tail_.empty()) {
      error_text = fmt::format("line stalled: {} bytes of an earlier epoch still waiting to go out", tail_.size());
      return WriteStatus::dropped;
    }
  }
  // A real UART or USB adapter reports its queue; a pty always reports 0 and relies on the tail.
  int queued = 0;
  if (::ioctl(fd_, TIOCOUTQ, &queued) != 0) queued = 0;
  const double allowed = nmea::line_bytes_per_second(options_.baud_bps) * options_.max_queue_s;
  if (queued > 0 && static_cast<double>(queued) + static_cast<double>(bytes.size()) > allowed) {
    ++serial_stats_.epochs_dropped_queue;
    error_text = fmt::format("line not keeping up: {} bytes still queued, {:.0f} allowed at {} baud", queued,
                             allowed, options_.baud_bps);
    return WriteStatus::dropped;
  }
  for (;;) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n >= 0 && static_cast<std::size_t>(n) == bytes.size()) return WriteStatus::ok;
    if (n > 0) {
      // Part of the epoch went out: the rest must follow before anything else does.
      tail_.assign(bytes.substr(static_cast<std::size_t>(n)));
      ++serial_stats_.epochs_completed_late;
      return WriteStatus::ok;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n == 0 || errno == EAGAIN || errno == EWOULDBLOCK) {
      error_text = "no room in the output buffer (line stalled)";
      return WriteStatus::dropped;
    }
    error_text = fmt::format("write to {} failed: {}", device_, posix::errno_text(errno));
    lose_device(posix::errno_text(errno));
    return WriteStatus::error;
  }
}

void SerialOutput::service() {
  if (fd_ < 0) {
    maybe_reopen();
    return;
  }
  std::uint64_t read_bytes = 0;  // taken by the receiver; the rest is discarded
  const posix::Drained input = posix::drain_input(fd_, client_input_budget, [this, &read_bytes](std::string_view bytes) {
    if (client_wrote(bytes, client_)) read_bytes += bytes.size();
  });
  serial_stats_.input_bytes_discarded += input.bytes - read_bytes;
  if (input.end != posix::Drained::End::empty) {
    // End of file on a tty, or EIO: the device hung up (unplugged, the pty's other side closed).
    lose_device(input.end == posix::Drained::End::closed ? "hung up" : posix::errno_text(input.error));
    return;
  }
  std::string error_text;
  (void)flush_tail(error_text);
}

void SerialOutput::flush() {
  for (int waited = 0; fd_ >= 0 && !tail_.empty() && waited < kFlushWaitMs; waited += 50) {
    std::string error_text;
    if (!flush_tail(error_text) || tail_.empty()) break;
    pollfd pfd{fd_, POLLOUT, 0};
    (void)::poll(&pfd, 1, 50);
  }
}

std::string SerialOutput::spec_text() const {
  return target_.usb ? fmt::format("serial:usb:{}@{}", to_string(*target_.usb), options_.baud_bps)
                     : fmt::format("serial:{}@{}", target_.device.string(), options_.baud_bps);
}

bool SerialOutput::set_baud(int baud_bps, std::string& error_text) {
  speed_t speed{};
  try {
    speed = speed_for(baud_bps);
  } catch (const std::invalid_argument& e) {
    error_text = e.what();
    return false;
  }
  options_.baud_bps = baud_bps;  // a reopen after a hang-up uses it too
  spec_text_ = spec_text();
  if (fd_ < 0) return true;
  flush();
  (void)::tcdrain(fd_);  // what was queued (the acknowledgement) leaves at the old rate
  termios tio{};
  if (::tcgetattr(fd_, &tio) != 0 || ::cfsetispeed(&tio, speed) != 0 || ::cfsetospeed(&tio, speed) != 0 ||
      ::tcsetattr(fd_, TCSANOW, &tio) != 0) {
    error_text = fmt::format("cannot set {} baud on {}: {}", baud_bps, device_, posix::errno_text(errno));
    return false;
  }
  return true;
}

void SerialOutput::check_modem_line(ModemLine line) {
  int bits = modem_bit(line);
  if (fd_ < 0 || ::ioctl(fd_, TIOCMBIC, &bits) != 0) {
    const int err = fd_ < 0 ? ENODEV : errno;
    throw std::runtime_error(fmt::format(
        "{}: {} has no {} modem control line ({}): {}", spec_text_, device_, to_string(line),
        err == ENOTTY || err == EINVAL ? "TIOCMBIC: not supported by this device"
                                       : fmt::format("TIOCMBIC: {}", posix::errno_text(err)),
        err == ENOTTY || err == EINVAL
            ? "a pseudo-terminal (pty output, socat pty pair) has no modem lines and cannot carry PPS; "
              "use a real UART or USB serial adapter, or --pps gpio:CHIP:LINE"
            : "the PPS pulse cannot be driven on it"));
  }
}

bool SerialOutput::set_modem_line(ModemLine line, bool asserted, std::string& error_text) {
  (line == ModemLine::rts ? rts_asserted_ : dtr_asserted_) = asserted;
  if (fd_ < 0) {
    error_text = fmt::format("{}: device lost", spec_text_);
    return false;
  }
  int bits = modem_bit(line);
  if (::ioctl(fd_, asserted ? TIOCMBIS : TIOCMBIC, &bits) != 0) {
    error_text = fmt::format("{} {} on {}: {}", asserted ? "TIOCMBIS" : "TIOCMBIC", to_string(line), device_,
                             posix::errno_text(errno));
    return false;
  }
  return true;
}

}  // namespace gpsemu::transport
