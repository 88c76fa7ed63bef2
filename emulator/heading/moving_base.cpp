// Moving-base geometry and the rover's relative position (see moving_base.hpp).
#include "emulator/heading/moving_base.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace gpsemu::heading {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kMaxOffsetM = 100.0;
/// The rover's noise stream ("RELP"): apart from the receiver's other streams.
constexpr std::uint64_t kRelPosStream = 0x52454C50;

}  // namespace

const char* to_string(Role role) {
  switch (role) {
    case Role::standalone: return "standalone";
    case Role::moving_base: return "moving-base";
    case Role::rover: return "rover";
  }
  return "standalone";
}

Role parse_role(const std::string& text) {
  for (const Role r : {Role::standalone, Role::moving_base, Role::rover}) {
    if (text == to_string(r)) return r;
  }
  throw std::invalid_argument(
      fmt::format("role: unknown role '{}' (accepted: standalone, moving-base, rover)", text));
}

AntennaOffset parse_antenna_offset(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string cell;
  while (std::getline(in, cell, ',')) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(cell, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < cell.size() && cell[used] == ' ') ++used;
    if (used == 0 || used != cell.size() || !std::isfinite(v) || std::abs(v) > kMaxOffsetM) {
      throw std::invalid_argument(fmt::format(
          "antenna-offset: '{}' is not a number of metres within +-{:g} in '{}' (FORWARD,RIGHT,DOWN)", cell,
          kMaxOffsetM, text));
    }
    values.push_back(v);
  }
  if (values.size() != 3) {
    throw std::invalid_argument(fmt::format(
        "antenna-offset: '{}' has {} values: give FORWARD,RIGHT,DOWN in metres (e.g. 0.5,0,-0.2)", text,
        values.size()));
  }
  return {values[0], values[1], values[2]};
}

Enu offset_enu(const AntennaOffset& a, double yaw_deg, double pitch_deg, double roll_deg) {
  const double cy = std::cos(yaw_deg * kDegToRad), sy = std::sin(yaw_deg * kDegToRad);
  const double cp = std::cos(pitch_deg * kDegToRad), sp = std::sin(pitch_deg * kDegToRad);
  const double cr = std::cos(roll_deg * kDegToRad), sr = std::sin(roll_deg * kDegToRad);
  const double f = a.forward_m, r = a.right_m, d = a.down_m;
  const double north = cy * cp * f + (cy * sp * sr - sy * cr) * r + (cy * sp * cr + sy * sr) * d;
  const double east = sy * cp * f + (sy * sp * sr + cy * cr) * r + (sy * sp * cr - cy * sr) * d;
  const double down = -sp * f + cp * sr * r + cp * cr * d;
  return {east, north, -down};
}

Ned baseline_ned(const AntennaOffset& base, const AntennaOffset& rover, double yaw_deg, double pitch_deg,
                 double roll_deg) {
  const Enu d = offset_enu(rover, yaw_deg, pitch_deg, roll_deg) - offset_enu(base, yaw_deg, pitch_deg, roll_deg);
  return {d.north_m, d.east_m, -d.up_m};
}

RoverRelPos::RoverRelPos(const MovingBaseOptions& options, std::uint64_t seed)
    : options_(options), rng_(seed, kRelPosStream) {}

RelativePosition RoverRelPos::at(UtcNs t, const std::optional<sources::Truth>& truth,
                               const std::optional<UtcNs>& last_corrections) {
  RelativePosition rel;
  rel.is_moving = true;
  // The noise runs every epoch, so a valid epoch's noise does not depend on the ones before it.
  const double sigma = options_.baseline_sigma_m;
  const Ned noise{sigma * rng_.normal(), sigma * rng_.normal(), sigma * rng_.normal()};
  const bool fresh = last_corrections && t >= *last_corrections &&
                     std::chrono::duration<double>(t - *last_corrections).count() <= options_.corrections_timeout_s;
  if (!truth || !truth->yaw_deg || !fresh) return rel;
  const Ned b = baseline_ned(options_.base_antenna, options_.antenna, *truth->yaw_deg, truth->tilt.pitch_deg,
                             truth->tilt.roll_deg);
  rel.north_m = b.north_m + noise.north_m;
  rel.east_m = b.east_m + noise.east_m;
  rel.down_m = b.down_m + noise.down_m;
  const double horizontal_m = std::hypot(rel.north_m, rel.east_m);
  rel.length_m = std::hypot(horizontal_m, rel.down_m);
  rel.acc_north_m = rel.acc_east_m = rel.acc_down_m = rel.acc_length_m = sigma;
  rel.diff_soln = true;
  rel.rel_pos_valid = true;
  rel.carrier = CarrierSolution::fixed;
  // The heading of the baseline and its 1 sigma: the cross-track error over the length.
  const double true_horizontal_m = std::hypot(b.north_m, b.east_m);
  if (true_horizontal_m > 10.0 * sigma && horizontal_m > 0.0) {
    double heading = std::atan2(rel.east_m, rel.north_m) / kDegToRad;
    if (heading < 0.0) heading += 360.0;
    rel.heading_deg = heading >= 360.0 ? 0.0 : heading;
    rel.acc_heading_deg = std::atan2(sigma, true_horizontal_m) / kDegToRad;
    rel.heading_valid = true;
  }
  return rel;
}

}  // namespace gpsemu::heading
