// Output specs written back as text (transport::to_string), for tests that compare a loaded
// configuration's outputs with what was given.
#pragma once

#include <string>
#include <vector>

#include "transport/output_spec.hpp"

namespace gpsemu::test {

inline std::vector<std::string> output_texts(const std::vector<transport::OutputSpec>& outputs) {
  std::vector<std::string> texts;
  for (const auto& spec : outputs) texts.push_back(transport::to_string(spec));
  return texts;
}

}  // namespace gpsemu::test
