// A UART as the receiver's port (`serial:DEVICE[@BAUD]`, `serial:usb:VID:PID[:SERIAL][@BAUD]`):
// termios raw 8N1, no flow control, non-blocking. Works alike on a board UART, a USB adapter and a
// pseudo-terminal (a socat pty pair stands in for a UART in the tests).
//
// Writes never block the epoch loop and never leave half an epoch on the line: before an epoch
// goes out, the kernel's output queue (TIOCOUTQ) must have room for it within what the line
// carries in one queue limit (default: one epoch period), else the whole epoch is dropped and
// counted. If the kernel takes only part of an epoch, the rest is kept and finished before any
// later epoch is written (later epochs are dropped meanwhile), so the far end only ever sees
// whole sentences. Whatever the far end writes (gpsd probes) is read and discarded.
//
// Hot replug: on a hang-up or write error the device is closed and looked for again every
// rescan interval: by path for `serial:DEVICE`, by USB identity through a PortLister for
// `serial:usb:...` (so ttyUSB0 coming back as ttyUSB1 is found), and reopened without a restart.
// The modem control lines (RTS, DTR) can carry a PPS pulse (see pps.hpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "nmea/line_budget.hpp"
#include "transport/output.hpp"
#include "transport/pps.hpp"
#include "transport/serial_ports.hpp"

namespace gpsemu::transport {

/// Which device a serial output uses: a path, or a USB adapter found by identity.
struct SerialTarget {
  std::filesystem::path device;    ///< "/dev/ttyS1", "/dev/ttyUSB0", a pty link; empty with `usb`
  std::optional<UsbSelector> usb;  ///< set: find the adapter by VID:PID[:SERIAL] (and re-find it)
};

struct SerialOptions {
  int baud_bps = nmea::kDefaultBaud;  ///< one of nmea::kStandardBauds (bits per second); 8N1
  /// Longest the kernel's output queue may be, as time on the line at baud_bps, before a new
  /// epoch is dropped instead of queued behind it (seconds). Runner: one epoch period.
  double max_queue_s = 1.0;
  /// How often a lost device is looked for again (milliseconds).
  std::chrono::milliseconds rescan_interval{1000};
};

/// Counters specific to a serial line, next to Output::stats().
struct SerialStats {
  std::uint64_t device_losses = 0;          ///< hang-ups and write errors that closed the device
  std::uint64_t reopens = 0;                ///< times the device was found and opened again
  std::uint64_t epochs_dropped_queue = 0;   ///< epochs dropped because the output queue was too long
  std::uint64_t epochs_completed_late = 0;  ///< epochs the kernel took in more than one write
  std::uint64_t input_bytes_discarded = 0;  ///< bytes the far end wrote to us, read and dropped
};

class SerialOutput final : public Output {
 public:
  /// Opens the device (for `usb`, the one adapter `lister` finds; the system's list when
  /// `lister` is null). Throws std::runtime_error naming the device: missing, not a serial
  /// device, permission denied, in use, baud not accepted; for `usb`: none or several adapters
  /// match. Throws std::invalid_argument for a baud that is not one of nmea::kStandardBauds.
  SerialOutput(SerialTarget target, SerialOptions options, std::shared_ptr<PortLister> lister = nullptr);
  ~SerialOutput() override;

  /// Reads and discards input; notices a hang-up; finishes a partly written epoch; while the
  /// device is lost, looks for it again (at most once per rescan interval).
  void service() override;
  /// The open device, or -1 while it is lost.
  [[nodiscard]] int poll_fd() const override { return fd_; }
  /// "serial:/tmp/gps@115200 (/dev/pts/4)" or "serial:usb:0403:6001@115200 (/dev/ttyUSB0)".
  [[nodiscard]] std::string describe() const override;
  /// Finishes a partly written epoch, waiting up to a second for the line.
  void flush() override;

  [[nodiscard]] bool is_open() const { return fd_ >= 0; }
  /// The device node currently (or last) open: "/dev/ttyUSB1", "/dev/pts/4".
  [[nodiscard]] const std::string& device() const { return device_; }
  [[nodiscard]] SerialOutput* serial_line() override { return this; }
  [[nodiscard]] const SerialOutput* serial_line() const override { return this; }
  [[nodiscard]] const SerialStats& serial_stats() const { return serial_stats_; }
  [[nodiscard]] int baud_bps() const { return options_.baud_bps; }

  /// Changes the line's speed (a u-blox client's CFG-PRT): finishes the partly written epoch,
  /// waits until the queued bytes are on the line (tcdrain), then sets the new baud. False with
  /// `error_text` for a baud not in nmea::kStandardBauds or one the driver refuses.
  bool set_baud(int baud_bps, std::string& error_text);

  /// Start-up check that the device has `line` (a pty has no modem lines). Throws
  /// std::runtime_error naming the device and the reason.
  void check_modem_line(ModemLine line);
  /// Asserts (TIOCMBIS) or clears (TIOCMBIC) `line`. The state is re-applied after a reopen.
  /// Returns false with `error_text` when the device is lost or the ioctl fails.
  bool set_modem_line(ModemLine line, bool asserted, std::string& error_text);

 protected:
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;

 private:
  ClientId client_ = new_client_id();  ///< the line has one client (a new one after the device was lost)
  void open_device(const std::string& path);
  [[nodiscard]] std::string spec_text() const;
  void lose_device(const std::string& why);
  void maybe_reopen();
  /// Writes what is left of a partly written epoch; false when the device was lost.
  bool flush_tail(std::string& error_text);
  void close_fd(bool let_queue_drain) noexcept;

  SerialTarget target_;
  SerialOptions options_;
  std::shared_ptr<PortLister> lister_;
  std::string spec_text_;  ///< "serial:/tmp/gps@115200"
  std::string device_;     ///< the device node open now (or last)
  int fd_ = -1;
  std::string tail_;       ///< the unwritten rest of a partly written epoch
  std::optional<bool> rts_asserted_, dtr_asserted_;  ///< requested modem line states
  std::string lost_reason_;
  std::chrono::steady_clock::time_point lost_since_{};
  std::chrono::steady_clock::time_point last_attempt_{};
  std::string last_problem_logged_;
  SerialStats serial_stats_;
  LogLimit loss_log_{1};  ///< "device lost" lines (a line that comes and goes): at most one a second
};

}  // namespace gpsemu::transport
