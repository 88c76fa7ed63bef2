#include <stdexcept>

#include "emulator/model/noise/noise_model.hpp"

namespace gpsemu::noise {

Model parse_model(const std::string& name) {
  if (name == "none") return Model::none;
  if (name == "cgrw") return Model::cgrw;
  if (name == "chrono") return Model::chrono;
  if (name == "gaussian") return Model::gaussian;
  if (name == "gauss-markov") return Model::gauss_markov;
  if (name == "composite") return Model::composite;
  throw std::invalid_argument("unknown noise model '" + name +
                              "' (accepted: cgrw, chrono, gaussian, gauss-markov, composite, none)");
}

std::string to_string(Model model) {
  switch (model) {
    case Model::none: return "none";
    case Model::cgrw: return "cgrw";
    case Model::chrono: return "chrono";
    case Model::gaussian: return "gaussian";
    case Model::gauss_markov: return "gauss-markov";
    case Model::composite: return "composite";
  }
  return "?";
}

}  // namespace gpsemu::noise
