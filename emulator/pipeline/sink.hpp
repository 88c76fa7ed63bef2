// Where every epoch's bytes go, for the emulator and replay alike: each receiver's outputs
// (--output specs, then the --tee copy), refused at start-up when a serial line cannot carry the
// epochs (serial_line_check.hpp), written to in one go an epoch, serviced between epochs (client
// input, new clients), flushed at the end, and summarised with their counts.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "transport/output.hpp"
#include "transport/output_spec.hpp"
#include "transport/serial_output.hpp"

namespace gpsemu {

/// One receiver's outputs (pipeline/run_settings.hpp builds them from a Config).
struct OutputSettings {
  std::vector<transport::OutputSpec> outputs;  ///< parsed --output specs
  std::optional<std::string> tee;    ///< a copy of everything sent, with send times
  bool realtime = true;              ///< paced (not --fast): sockets and queues behave as live
  double rate_hz = 1.0;              ///< epochs a second (serial line budget and queue)
  /// The widest epoch in bytes, for the serial line check; empty: no check.
  std::function<std::size_t()> widest_epoch_bytes;
};

/// One receiver's outputs, after checking every serial line's budget (before anything is opened).
/// Throws std::exception with a clear message.
[[nodiscard]] std::vector<std::unique_ptr<transport::Output>> open_outputs(const OutputSettings& settings);

class Sink {
 public:
  /// Opens one receiver's outputs (open_outputs()). Returns the receiver's index.
  std::size_t open(const OutputSettings& settings) { return add(open_outputs(settings)); }
  /// Adds one receiver's outputs made by the caller (tests: recording fakes). Returns its index.
  std::size_t add(std::vector<std::unique_ptr<transport::Output>> outputs);

  [[nodiscard]] std::size_t receivers() const { return receivers_.size(); }
  [[nodiscard]] const std::vector<std::unique_ptr<transport::Output>>& outputs(std::size_t i) const {
    return receivers_.at(i);
  }
  /// Client input of receiver i's outputs goes to `input` (its channel's encoders).
  void attach_client_input(std::size_t i, transport::ClientInput* input);

  /// Work due before the next write of receiver i that need not be on time (outputs' prepare_epoch).
  void prepare(std::size_t i);
  /// Writes receiver i's epoch to each of its outputs. Safe to call for different receivers from
  /// two threads at once (nothing shared).
  void write(std::size_t i, std::string_view bytes) {
    for (const auto& out : receivers_[i]) (void)out->write_epoch(bytes);
  }
  /// Services every output (between epochs when nothing is polled: --fast).
  void service_all();
  /// True when no output of any receiver took an epoch and some epochs failed (every output could
  /// not be written: a full disk, /dev/full). Epochs dropped for want of a client (a TCP server
  /// nobody connected to) are no failure.
  [[nodiscard]] bool none_took_any() const;
  /// True when every output of every receiver is gone for good (each a pipe whose reader left).
  [[nodiscard]] bool all_gone() const;
  void flush();
  /// Every output of every receiver takes over its destination (Output::commit(): files are
  /// truncated), once everything that can fail at start-up is open. Throws what an output throws.
  void commit();

  /// Appends the descriptors to poll for client input, and the output each belongs to.
  void list_inputs(std::vector<int>& fds, std::vector<transport::Output*>& owners) const;
  /// The first serial output of any receiver (a modem PPS line drives its RTS/DTR), or nullptr.
  [[nodiscard]] transport::SerialOutput* first_serial() const;

  /// "receiver 3: " when there are many receivers, else "".
  [[nodiscard]] std::string who(std::size_t i) const;
  /// One "NMEA on ..." line an output of receiver i (`protocol`: what it writes).
  void log_opened(std::size_t i, std::string_view protocol = "NMEA") const;
  /// One line an output of receiver i: epochs written, bytes, dropped, failed.
  void log_summary(std::size_t i) const;

 private:
  std::vector<std::vector<std::unique_ptr<transport::Output>>> receivers_;
};

}  // namespace gpsemu
