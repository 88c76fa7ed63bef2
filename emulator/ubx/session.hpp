// One u-blox port as the emulator sees it, pure (PX4-GPSDrivers' shape; the UBX encoder of a
// receiver channel is a thin adapter over it): what the client writes goes in, the answers
// (ACKs, poll answers) come out at once through take_reply() for the loop to write before the
// next epoch, the effects the emulator must apply (measurement period, baud, cold start) through
// take_effects(), and each epoch's bytes (NAV messages, NMEA sentences, then NAV-EOE, as the
// settings turn them on: output.hpp) through append_solution().
//
// The solutions lie on the start grid (the epochs the session is stepped at: --rate's) until the
// client asks for another period; then on the solution grid it asks for (solution_grid.hpp): an
// epoch off that grid writes nothing. The emulator loop steps the session on that grid itself
// (the MeasurementPeriodChanged effect); a caller stepping at a fixed rate gets it thinned.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/nav.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {

struct SessionSettings {
  StartSettings start;           ///< model, port, start rate, NMEA sentences and UBX messages on
  nmea::FormatOptions format;    ///< how the NMEA part is written (its sentence set is ignored)
  double speed_sigma_mps = 0.0;  ///< 1-sigma speed error reported as sAcc (metres per second)
  StoredLayers stored;           ///< BBR and flash at power-up (--receiver-state); RAM is built from them
};

class Session {
 public:
  explicit Session(SessionSettings settings);

  /// Bytes a client wrote (any chunking).
  void client_wrote(std::string_view bytes);
  /// The answers not yet written (empties them).
  [[nodiscard]] std::string take_reply();
  /// MeasurementPeriodChanged, BaudChanged and ColdStart effects not yet taken (empties them).
  /// At power-up: the period and baud the stored layers give, when they differ from the start's.
  [[nodiscard]] std::vector<Effect> take_effects();
  /// Whether a new solution period waits in take_effects() (the loop reschedules at once).
  [[nodiscard]] bool period_change_pending() const;

  /// Appends the epoch's bytes for `fix` to `out`: nothing off the measurement grid.
  void append_solution(const nmea::Fix& fix, std::string& out);

  /// Whether a solution falls at `t`: any epoch while the period is the start one, else those on
  /// the asked solution grid.
  [[nodiscard]] bool on_solution_grid(nmea::UtcTime t) const;

  [[nodiscard]] const ConfigMachine& machine() const { return machine_; }
  [[nodiscard]] std::uint64_t solutions() const { return solutions_; }

 private:
  SessionSettings settings_;
  ConfigMachine machine_;
  std::string reply_;
  std::vector<Effect> effects_;
  std::vector<MessageId> polled_;
  std::uint64_t solutions_ = 0;
  std::optional<nmea::UtcTime> first_epoch_;
  std::optional<std::chrono::milliseconds> time_to_first_fix_;
};

}  // namespace gpsemu::ubx
