// Test support for the noise models: a NoiseConfig of one model from its parameters, and the check
// that bad parameters throw std::invalid_argument naming the parameter.
#pragma once

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "emulator/model/noise/noise_model.hpp"

namespace gpsemu::test {

inline noise::NoiseConfig cgrw(const noise::CgrwParams& p) {
  noise::NoiseConfig c;
  c.model = noise::Model::cgrw;
  c.cgrw = p;
  return c;
}

inline noise::NoiseConfig chrono(double mean, double sigma, double rate, double vmax, double amax) {
  noise::NoiseConfig c;
  c.model = noise::Model::chrono;
  c.chrono = {mean, sigma, rate, vmax, amax};
  return c;
}

inline noise::NoiseConfig gaussian(noise::GaussianAxis east, noise::GaussianAxis north, noise::GaussianAxis up) {
  noise::NoiseConfig c;
  c.model = noise::Model::gaussian;
  c.gaussian = {east, north, up};
  return c;
}

inline noise::NoiseConfig gauss_markov(noise::GaussMarkovAxis east, noise::GaussMarkovAxis north,
                                       noise::GaussMarkovAxis up) {
  noise::NoiseConfig c;
  c.model = noise::Model::gauss_markov;
  c.gauss_markov = {east, north, up};
  return c;
}

/// make_noise_model(c, 1) throws std::invalid_argument whose message contains `name`.
inline void expect_throw_naming(const noise::NoiseConfig& c, const std::string& name) {
  try {
    (void)noise::make_noise_model(c, 1);
    ADD_FAILURE() << "no exception; expected one naming " << name;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

}  // namespace gpsemu::test
