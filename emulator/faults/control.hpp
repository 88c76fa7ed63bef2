// The control socket's protocol (--control unix:PATH): one JSON object a line in, one JSON object
// a line out, in gpsd's habits (every answer has a "class"; errors are {"class":"ERROR",
// "message":...}; unknown top-level fields are ignored). Pure: text in, text out, acting on the
// receivers' fault timelines; the socket itself is transport/posix/unix_line_server.hpp.
//
//   {"fault":"jam","db":25,"ramp_s":5,"receiver":0}  a fault from the next epoch ("duration": s; absent:
//                                                   until cleared); parameters as in a [[fault]] table
//   {"clear":"jam","receiver":0}                     ends that kind's faults at the next epoch ("all": every kind)
//   {"status":true}                                  each receiver's last epoch and its faults
//   {"watch":true,"receiver":0}                      (the control socket's: one EPOCH line an epoch follows)
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/faults/fault_timeline.hpp"

namespace gpsemu::faults {

class FaultControl {
 public:
  /// Receiver i's timeline is receivers[i].
  explicit FaultControl(std::vector<FaultTimeline*> receivers) : receivers_(std::move(receivers)) {}

  /// The answer to one line (without its end), as one line of JSON without '\n'. Never throws.
  [[nodiscard]] std::string handle(std::string_view line);
  /// What the status answer adds to receiver i's entry: the members of a JSON object ("{...}"),
  /// e.g. the error against the truth and the clients (emulator/ui/hub.hpp).
  void set_status_extra(std::function<std::string(std::size_t)> extra) { status_extra_ = std::move(extra); }
  /// Requests refused before parsing (json_shape.hpp: nested too deep, a key twice).
  [[nodiscard]] std::uint64_t refused_shape() const { return refused_shape_; }

 private:
  std::vector<FaultTimeline*> receivers_;
  std::function<std::string(std::size_t)> status_extra_;
  std::uint64_t refused_shape_ = 0;
};

/// {"class":"ERROR","message":MESSAGE}
[[nodiscard]] std::string control_error(std::string_view message);

}  // namespace gpsemu::faults
