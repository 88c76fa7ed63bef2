#include "emulator/model/noise/gauss_markov_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gpsemu::noise {
namespace {

// I_k(a) = integral_0^a u^k exp(-2u) du for k = 0, 1, 2; by series below a = 0.5 (the closed
// forms cancel catastrophically for small a: I_2 ~ a^3 / 3).
double integral(int k, double a) {
  if (k == 0) return -std::expm1(-2.0 * a) / 2.0;
  if (a < 0.5) {
    // sum_n (-2)^n a^(n+k+1) / (n! (n+k+1))
    double sum = 0.0, term = std::pow(a, k + 1);  // (-2a)^n / n! * a^(k+1)
    for (int n = 0; n < 60; ++n) {
      sum += term / (n + k + 1);
      term *= -2.0 * a / (n + 1);
      if (std::abs(term) < 1e-18 * std::abs(sum)) break;
    }
    return sum;
  }
  const double e = std::exp(-2.0 * a);
  if (k == 1) return (1.0 - e * (1.0 + 2.0 * a)) / 4.0;
  return (1.0 - e * (1.0 + 2.0 * a + 2.0 * a * a)) / 4.0;
}

}  // namespace

void validate_gauss_markov_axes(const std::array<GaussMarkovAxis, 3>& axes, int order) {
  if (order != 1 && order != 2) {
    throw std::invalid_argument("gauss-markov.order must be 1 or 2 (got " + std::to_string(order) + ")");
  }
  const char* names[] = {"east", "north", "up"};
  for (std::size_t i = 0; i < 3; ++i) {
    std::ostringstream os;
    if (!(axes[i].sigma_m >= 0.0) || !std::isfinite(axes[i].sigma_m)) {
      os << "gauss-markov." << names[i] << ".sigma_m must be finite and >= 0 (got "
         << axes[i].sigma_m << ")";
    } else if (!(axes[i].tau_s > 0.0) || !std::isfinite(axes[i].tau_s)) {
      os << "gauss-markov." << names[i] << ".tau_s must be finite and > 0 seconds (got "
         << axes[i].tau_s << ")";
    }
    if (!os.str().empty()) throw std::invalid_argument(os.str());
  }
}

double gauss_markov_autocorrelation(int order, double lag_s, double tau_s) {
  const double a = std::abs(lag_s) / tau_s;
  return order == 2 ? (1.0 + a) * std::exp(-a) : std::exp(-a);
}

GaussMarkovNoise::GaussMarkovNoise(const std::array<GaussMarkovAxis, 3>& axes, std::uint64_t seed,
                                   int order)
    : axes_(axes), order_(order), rngs_{Rng(seed, 0), Rng(seed, 1), Rng(seed, 2)} {
  validate_gauss_markov_axes(axes_, order_);
}

void GaussMarkovNoise::restart() {
  for (std::size_t i = 0; i < 3; ++i) {
    rngs_[i].reset();
    const double s = axes_[i].sigma_m;
    x_m_[i] = s * rngs_[i].normal();
    // Order 2: stationary covariance sigma^2 [[1, 1], [1, 2]] of (x, y).
    y_m_[i] = order_ == 2 ? x_m_[i] + s * rngs_[i].normal() : 0.0;
  }
  started_ = true;
}

void GaussMarkovNoise::step(std::size_t i, double dt_s) {
  const double s = axes_[i].sigma_m;
  const double a = dt_s / axes_[i].tau_s;
  Rng& rng = rngs_[i];
  if (order_ == 1) {
    x_m_[i] = std::exp(-a) * x_m_[i] + s * std::sqrt(-std::expm1(-2.0 * a)) * rng.normal();
    return;
  }
  // Transition exp(-a) [[1, a], [0, 1]]; process noise 4 sigma^2 [[I2, I1], [I1, I0]].
  const double e = std::exp(-a);
  const double x = e * (x_m_[i] + a * y_m_[i]);
  const double y = e * y_m_[i];
  const double q00 = 4.0 * s * s * integral(2, a);
  const double q01 = 4.0 * s * s * integral(1, a);
  const double q11 = 4.0 * s * s * integral(0, a);
  const double l00 = std::sqrt(q00);
  const double l10 = l00 > 0.0 ? q01 / l00 : 0.0;
  const double l11 = std::sqrt(std::max(0.0, q11 - l10 * l10));
  const double z0 = rng.normal(), z1 = rng.normal();
  x_m_[i] = x + l00 * z0;
  y_m_[i] = y + l10 * z0 + l11 * z1;
}

Enu GaussMarkovNoise::offset_at(std::chrono::nanoseconds since_start) {
  if (!started_ || since_start < last_) {
    restart();
  } else if (since_start > last_) {
    const double dt_s = static_cast<double>((since_start - last_).count()) / 1e9;
    for (std::size_t i = 0; i < 3; ++i) step(i, dt_s);
  }
  last_ = since_start;
  return {x_m_[0], x_m_[1], x_m_[2]};
}

}  // namespace gpsemu::noise
