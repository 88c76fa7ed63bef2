// When a u-blox computes its navigation solutions: every measRate x navRate milliseconds (CFG-RATE,
// CFG-RATE-MEAS/NAV), aligned to the top of second zero of the week of the reference time system
// (timeRef: 1 GPS, so iTOW is a multiple of the period; 0 UTC), and never faster than the model
// can navigate (its data sheet's highest navigation update rate; a faster setting is acknowledged,
// as the receivers do, and solutions come at that highest rate). Pure.
#pragma once

#include <chrono>
#include <cstdint>

#include "emulator/ubx/model.hpp"
#include "emulator/ubx/settings.hpp"

namespace gpsemu::ubx {

using SolutionTime = std::chrono::sys_time<std::chrono::nanoseconds>;

/// The shortest time between navigation solutions `model` delivers: NEO-M8N 100 ms (10 Hz with
/// concurrent GNSS, its default), NEO-M9N 40 ms (25 Hz), ZED-F9P 50 ms (20 Hz, RTK), generic
/// 25 ms (the protocol's shortest measurement period).
[[nodiscard]] std::chrono::milliseconds fastest_solution_period(ReceiverModel model);

/// The time between the solutions `s` asks for on `model`: measRate x navRate, at least the
/// model's fastest_solution_period().
[[nodiscard]] std::chrono::milliseconds solution_period(const Settings& s, ReceiverModel model);

/// The solution grid: a period and the reference time system it is aligned to.
struct SolutionGrid {
  std::chrono::milliseconds period{1000};
  std::uint16_t time_ref = 1;  ///< CFG-RATE timeRef: 0 UTC, else GPS (GLONASS, BeiDou, Galileo: as GPS)

  /// The first solution time strictly after `t`.
  [[nodiscard]] SolutionTime next_after(SolutionTime t) const;
  /// Whether a solution falls at `t`.
  [[nodiscard]] bool contains(SolutionTime t) const;
};

/// The grid `s` asks for on `model`.
[[nodiscard]] SolutionGrid solution_grid(const Settings& s, ReceiverModel model);

}  // namespace gpsemu::ubx
