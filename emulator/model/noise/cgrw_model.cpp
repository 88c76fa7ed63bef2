#include "emulator/model/noise/cgrw_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace gpsemu::noise {

CgrwParams cgrw_preset(double width_m) {
  if (!(width_m > 0.0) || !std::isfinite(width_m)) {
    std::ostringstream os;
    os << "cgrw preset width_m must be positive and finite (got " << width_m << ")";
    throw std::invalid_argument(os.str());
  }
  CgrwParams p;
  p.east = {width_m, kPresetD1PerWidth * width_m, kPresetD2PerWidth * width_m,
            kPresetSigmaD2PerWidth * width_m};
  p.north = p.east;
  const double up_m = kPresetUpPerHorizontal * width_m;
  p.up = {up_m, kPresetD1PerWidth * up_m, kPresetD2PerWidth * up_m,
          kPresetSigmaD2PerWidth * up_m};
  p.rate_hz = 1.0;
  p.window_s = 300.0;
  return p;
}

void validate_cgrw_params(const CgrwParams& params) {
  std::ostringstream os;
  if (!(params.rate_hz > 0.0) || !std::isfinite(params.rate_hz)) {
    os << "cgrw.rate_hz must be positive and finite (got " << params.rate_hz << ")";
  } else if (!(params.window_s > 0.0) || !std::isfinite(params.window_s)) {
    os << "cgrw.window_s must be positive and finite (got " << params.window_s << ")";
  } else if (const double n = params.window_s * params.rate_hz;
             n < kCgrwMinWindowSamples || n > kCgrwMaxWindowSamples) {
    os << "cgrw.window_s x cgrw.rate_hz must be " << kCgrwMinWindowSamples << " to "
       << kCgrwMaxWindowSamples << " samples (got " << params.window_s << " s x "
       << params.rate_hz << " Hz)";
  }
  if (!os.str().empty()) throw std::invalid_argument(os.str());
  validate_cgrw_axis(params.east, "cgrw.east");
  validate_cgrw_axis(params.north, "cgrw.north");
  validate_cgrw_axis(params.up, "cgrw.up");
}

namespace {
std::array<CgrwFit, 3> fit_all(const CgrwParams& params) {
  validate_cgrw_params(params);
  const double window = params.window_s * params.rate_hz;
  return {fit_cgrw_axis(params.east, window, "cgrw.east"),
          fit_cgrw_axis(params.north, window, "cgrw.north"),
          fit_cgrw_axis(params.up, window, "cgrw.up")};
}
}  // namespace

CgrwNoise::CgrwNoise(const CgrwParams& params, std::uint64_t seed)
    : fits_(fit_all(params)),
      axes_{Axis{fits_[0].internal, Rng(seed, 0)}, Axis{fits_[1].internal, Rng(seed, 1)},
            Axis{fits_[2].internal, Rng(seed, 2)}},
      rate_hz_(params.rate_hz),
      burn_in_steps_(0) {
  const double window = params.window_s * params.rate_hz;
  for (const CgrwFit& f : fits_)
    burn_in_steps_ = std::max(burn_in_steps_, cgrw_burn_in_steps(f.internal, window));
  restart();
}

void CgrwNoise::restart() {
  for (Axis& a : axes_) {
    a.rng.reset();
    a.p_m = a.v_m = 0.0;
  }
  // The three axes step side by side (each on its own numbers, as one after the other would): the
  // steps of one axis form a chain of dependent operations, and three chains overlap in the CPU.
  for (std::size_t i = 0; i < burn_in_steps_; ++i) {
    axes_[0].step();
    axes_[1].step();
    axes_[2].step();
  }
  for (Axis& a : axes_) {
    // The burn-in's last step is step 0; the one before it is p_0 - v_0.
    a.node_m[0] = a.p_m - a.v_m;
    a.node_m[1] = a.p_m;
    a.step();
    a.node_m[2] = a.p_m;
    a.step();
    a.node_m[3] = a.p_m;
  }
  base_ = 0;
}

void CgrwNoise::advance_to(std::int64_t base) {
  if (base < base_) restart();
  for (; base_ < base; ++base_) {
    for (Axis& a : axes_) {
      a.step();
      a.node_m = {a.node_m[1], a.node_m[2], a.node_m[3], a.p_m};
    }
  }
}

Enu CgrwNoise::offset_at(std::chrono::nanoseconds since_start) {
  // Division by 1e9 (exact when the product is a whole number of seconds times the rate), so a
  // time on the step grid lands exactly on its node.
  const double x = std::max(0.0, static_cast<double>(since_start.count()) * rate_hz_ / 1e9);
  const double k = std::floor(x);
  const double s = x - k;
  advance_to(static_cast<std::int64_t>(k));
  // Cubic Hermite basis on [0, 1].
  const double r = 1.0 - s;
  const double h00 = (1.0 + 2.0 * s) * r * r;
  const double h10 = s * r * r;
  const double h01 = s * s * (3.0 - 2.0 * s);
  const double h11 = -s * s * r;
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& n = axes_[i].node_m;
    const double slope0 = 0.5 * (n[2] - n[0]);  // (v into node + v out of node) / 2, m per step
    const double slope1 = 0.5 * (n[3] - n[1]);
    out[i] = h00 * n[1] + h10 * slope0 + h01 * n[2] + h11 * slope1;
  }
  return {out[0], out[1], out[2]};
}

}  // namespace gpsemu::noise
