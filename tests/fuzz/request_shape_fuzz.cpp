// libFuzzer target for the checks every client's JSON and every TOML file pass before a parser sees
// them (faults/json_shape.hpp, config/toml_shape.hpp): the input as a control request and as a
// config text. Checks: nothing crashes; a JSON text the shape check lets through and nlohmann
// parses is no deeper than kMaxJsonDepth and has no key twice in an object; a TOML text it lets
// through goes to toml++ (which then never recurses past kMaxTomlKeyParts / kMaxTomlNesting).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "emulator/config/config.hpp"
#include "emulator/config/toml_shape.hpp"
#include "emulator/faults/json_shape.hpp"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

/// The deepest nesting of a parsed value, and whether some object repeats a key (the DOM keeps
/// the last one, so a repeat shows as fewer members than the text's keys: checked by the SAX pass).
std::size_t depth_of(const nlohmann::json& j) {
  std::size_t deepest = 0;
  if (j.is_object() || j.is_array()) {
    for (const auto& v : j) deepest = std::max(deepest, depth_of(v));
    return deepest + 1;
  }
  return 0;
}

struct KeyRepeats : nlohmann::json_sax<nlohmann::json> {
  std::vector<std::set<std::string>> objects;
  bool repeated = false;
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override {
    objects.emplace_back();
    return true;
  }
  bool key(string_t& k) override {
    repeated = repeated || !objects.back().insert(k).second;
    return true;
  }
  bool end_object() override {
    objects.pop_back();
    return true;
  }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (!gpsemu::faults::json_shape_problem(text)) {
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (!j.is_discarded()) {
      check(depth_of(j) <= gpsemu::faults::kMaxJsonDepth);
      KeyRepeats sax;
      (void)nlohmann::json::sax_parse(text, &sax);
      // Escaped spellings of one key ("a" and "\u0061") are one key to the parser, two texts to
      // the check: only plain keys are asserted.
      if (text.find('\\') == std::string_view::npos) check(!sax.repeated);
    }
  }
  try {
    gpsemu::check_toml_shape(text, "config file", "fuzz.toml");
    try {
      (void)toml::parse(text, std::string_view("fuzz.toml"));
    } catch (const toml::parse_error&) {
    }
  } catch (const gpsemu::ConfigError&) {
  }
  return 0;
}
