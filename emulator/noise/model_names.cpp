#include <stdexcept>

#include "emulator/noise/noise_model.hpp"

namespace gpsemu::noise {

Model parse_model(const std::string& name) {
  if (name == "none") return Model::none;
  if (name == "cgrw") return Model::cgrw;
  if (name == "gaussian") return Model::gaussian;
  throw std::invalid_argument("unknown noise model '" + name + "' (accepted: cgrw, gaussian, none)");
}

std::string to_string(Model model) {
  switch (model) {
    case Model::none: return "none";
    case Model::cgrw: return "cgrw";
    case Model::gaussian: return "gaussian";
  }
  return "?";
}

}  // namespace gpsemu::noise
