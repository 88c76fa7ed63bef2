#include "emulator/sources/sim.hpp"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::sources {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

/// Degrees true in [0, 360) of an East/North direction.
double heading_of(double east, double north) {
  const double deg = std::atan2(east, north) / kDegToRad;
  return deg < 0.0 ? deg + 360.0 : deg;
}

double seconds_since(UtcNs start, UtcNs t) {
  return std::chrono::duration<double>(t - start).count();
}

/// At the origin, facing --sim-heading.
class Stationary final : public PoseSource {
 public:
  explicit Stationary(double heading_deg) : heading_deg_(heading_deg) {}
  std::optional<Truth> truth_at(UtcNs) override { return Truth{{}, {}, heading_deg_, {}}; }
  std::string describe() const override { return "sim:stationary (at the origin)"; }

 private:
  double heading_deg_;
};

/// Drives from the origin along a heading at constant speed, then stops and stays.
class Line final : public PoseSource {
 public:
  Line(const SimOptions& o, UtcNs start) : options_(o), start_(start) {
    dir_ = {std::sin(o.heading_deg * kDegToRad), std::cos(o.heading_deg * kDegToRad), 0.0};
    yaw_deg_ = heading_of(dir_.east_m, dir_.north_m);
  }
  std::optional<Truth> truth_at(UtcNs t) override {
    const double s = std::clamp(seconds_since(start_, t), 0.0, options_.drive_time_s);
    const bool moving = s < options_.drive_time_s && seconds_since(start_, t) >= 0.0;
    return Truth{(options_.speed_mps * s) * dir_, moving ? options_.speed_mps * dir_ : Enu{}, yaw_deg_, {}};
  }
  std::string describe() const override {
    return fmt::format("sim:line ({} m/s heading {} deg for {} s, then stopped)", options_.speed_mps,
                       options_.heading_deg, options_.drive_time_s);
  }

 private:
  SimOptions options_;
  UtcNs start_;
  Enu dir_;
  double yaw_deg_ = 0.0;  ///< the car faces its direction of travel, also once stopped
};

/// Counter-clockwise loop centred on the origin, starting at its southern point heading east.
class Circle final : public PoseSource {
 public:
  Circle(const SimOptions& o, UtcNs start) : options_(o), start_(start) {}
  std::optional<Truth> truth_at(UtcNs t) override {
    const double r = options_.radius_m;
    const double w = options_.speed_mps / r;  // rad/s
    const double a = w * std::max(0.0, seconds_since(start_, t));
    // Counter-clockwise: the car faces east at the start and turns left at w rad/s.
    return Truth{{r * std::sin(a), -r * std::cos(a), 0.0},
                 {options_.speed_mps * std::cos(a), options_.speed_mps * std::sin(a), 0.0},
                 heading_of(std::cos(a), std::sin(a)),
                 {}};
  }
  std::string describe() const override {
    return fmt::format("sim:circle (radius {} m at {} m/s)", options_.radius_m, options_.speed_mps);
  }

 private:
  SimOptions options_;
  UtcNs start_;
};

/// Drives straight segments between waypoints, each at its own speed.
class Waypoints final : public PoseSource {
 public:
  Waypoints(std::vector<Waypoint> points, bool loop, UtcNs start, std::string file)
      : points_(std::move(points)), loop_(loop), start_(start), file_(std::move(file)) {
    if (loop_) points_.push_back(points_.front());
    leg_start_s_.push_back(0.0);
    std::optional<double> yaw;  // a leg of length 0 keeps the heading before it
    for (std::size_t i = 0; i + 1 < points_.size(); ++i) {
      leg_start_s_.push_back(leg_start_s_.back() + length(i) / points_[i].speed_mps);
      const Enu d = points_[i + 1].position_m - points_[i].position_m;
      if (d.east_m != 0.0 || d.north_m != 0.0) yaw = heading_of(d.east_m, d.north_m);
      leg_yaw_deg_.push_back(yaw);
    }
  }
  std::optional<Truth> truth_at(UtcNs t) override {
    double s = std::max(0.0, seconds_since(start_, t));
    const double total = leg_start_s_.back();
    if (loop_ && total > 0.0) s = std::fmod(s, total);
    if (s >= total || points_.size() == 1) {
      return Truth{points_.back().position_m, {}, leg_yaw_deg_.empty() ? std::nullopt : leg_yaw_deg_.back(), {}};
    }
    std::size_t i = 0;
    while (i + 2 < leg_start_s_.size() && leg_start_s_[i + 1] <= s) ++i;
    const Enu d = points_[i + 1].position_m - points_[i].position_m;
    const double len = length(i);
    const Enu dir = len > 0.0 ? (1.0 / len) * d : Enu{};
    const double travelled = (s - leg_start_s_[i]) * points_[i].speed_mps;
    return Truth{points_[i].position_m + travelled * dir, points_[i].speed_mps * dir, leg_yaw_deg_[i], {}};
  }
  std::string describe() const override {
    return fmt::format("sim:waypoints:{} ({} waypoints, {:.1f} s{})", file_, points_.size(),
                       leg_start_s_.back(), loop_ ? ", looping" : ", then stopped");
  }

 private:
  double length(std::size_t i) const {
    const Enu d = points_[i + 1].position_m - points_[i].position_m;
    return std::sqrt(d.east_m * d.east_m + d.north_m * d.north_m + d.up_m * d.up_m);
  }
  std::vector<Waypoint> points_;
  bool loop_;
  UtcNs start_;
  std::string file_;
  std::vector<double> leg_start_s_;
  std::vector<std::optional<double>> leg_yaw_deg_;  ///< heading of each leg (degrees true)
};

void check_options(const SimOptions& o) {
  if (!(o.speed_mps > 0.0) || !std::isfinite(o.speed_mps)) {
    throw std::invalid_argument("sim-speed must be a positive number of metres per second");
  }
  if (!(o.radius_m > 0.0) || !std::isfinite(o.radius_m)) {
    throw std::invalid_argument("sim-radius must be a positive number of metres");
  }
  if (!(o.drive_time_s >= 0.0) || !std::isfinite(o.drive_time_s)) {
    throw std::invalid_argument("sim-drive-time must be zero or a positive number of seconds");
  }
}

}  // namespace

std::unique_ptr<PoseSource> make_sim_source(const std::string& name, const SimOptions& options,
                                            const LocalFrame& frame, UtcNs start) {
  check_options(options);
  if (name == "stationary") return std::make_unique<Stationary>(options.heading_deg);
  if (name == "line") return std::make_unique<Line>(options, start);
  if (name == "circle") return std::make_unique<Circle>(options, start);
  if (name.rfind("waypoints:", 0) == 0) {
    const std::string file = name.substr(10);
    return std::make_unique<Waypoints>(read_waypoints(file, frame, options.speed_mps), options.loop,
                                       start, file);
  }
  throw std::invalid_argument(fmt::format(
      "unknown simulator scenario 'sim:{}' (accepted: sim:stationary, sim:line, sim:circle, "
      "sim:waypoints:FILE)",
      name));
}

}  // namespace gpsemu::sources
