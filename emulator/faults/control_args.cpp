#include "emulator/faults/control_args.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/faults/catalogue.hpp"

namespace gpsemu::faults {
namespace {

using nlohmann::json;

/// "speed_mps" -> "speed-mps".
std::string dashed(std::string_view key) {
  std::string s(key);
  for (char& c : s) {
    if (c == '_') c = '-';
  }
  return s;
}

/// "--speed-mps|--speed": a key's flags.
std::string flags_of(std::string_view key) {
  const std::string full = "--" + dashed(key), short_form = "--" + dashed(key_without_unit(key));
  return full == short_form ? full : full + "|" + short_form;
}

std::string flag_list(const std::vector<std::string_view>& keys) {
  std::string out;
  for (const std::string_view key : keys) out += (out.empty() ? "" : ", ") + flags_of(key);
  return out.empty() ? "none" : out;
}

/// The key `flag` (without its "--") stands for among `keys`.
std::optional<std::string_view> key_of_flag(std::string_view flag, const std::vector<std::string_view>& keys) {
  for (const std::string_view key : keys) {
    if (flag == dashed(key) || flag == dashed(key_without_unit(key))) return key;
  }
  return std::nullopt;
}

/// "25" as a number, anything else as a string.
json value_of(const std::string& text) {
  try {
    std::size_t used = 0;
    const double x = std::stod(text, &used);
    if (used == text.size()) return x;
  } catch (const std::exception&) {
  }
  return text;
}

/// Adds the flags words[from..] to `message`: each one of `keys` (named `what` in messages).
void add_flags(json& message, const std::vector<std::string>& words, std::size_t from,
               const std::vector<std::string_view>& keys, const std::string& what) {
  for (std::size_t i = from; i < words.size(); ++i) {
    const std::string& word = words[i];
    if (word.rfind("--", 0) != 0 || word.size() == 2)
      throw std::invalid_argument(fmt::format("ctl {}: unexpected word '{}' (flags: {})", what, word, flag_list(keys)));
    std::string name = word.substr(2);
    std::optional<std::string> value;
    if (const std::size_t eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name.resize(eq);
    }
    const std::optional<std::string_view> key = key_of_flag(name, keys);
    if (!key) throw std::invalid_argument(fmt::format("ctl {}: unknown flag --{} (flags: {})", what, name, flag_list(keys)));
    if (!value) {
      if (i + 1 < words.size() && words[i + 1].rfind("--", 0) != 0) {
        value = words[++i];
      } else if (*key == "detected") {
        value = "true";
      } else {
        throw std::invalid_argument(fmt::format("ctl {}: --{} needs a value", what, name));
      }
    }
    const std::string k(*key);
    if (message.contains(k)) throw std::invalid_argument(fmt::format("ctl {}: --{} given twice", what, name));
    message[k] = value_of(*value);
  }
}

}  // namespace

std::string control_request_of(const std::vector<std::string>& words) {
  if (words.empty()) throw std::invalid_argument("ctl: expected a command after PATH: KIND [--FLAG VALUE]..., clear KIND, status or send JSON");
  const std::string& command = words[0];
  if (command == "status") {
    if (words.size() != 1) throw std::invalid_argument(fmt::format("ctl status: unexpected word '{}'", words[1]));
    return R"({"status":true})";
  }
  if (command == "send") {
    if (words.size() != 2) throw std::invalid_argument("ctl send: expected one JSON line (quoted as one word)");
    return words[1];
  }
  json message;
  if (command == "clear") {
    if (words.size() < 2 || words[1].rfind("--", 0) == 0) throw std::invalid_argument("ctl clear: expected a fault kind or all");
    if (words[1] != "all" && !parse_kind(words[1]))
      throw std::invalid_argument(fmt::format("ctl clear: unknown fault '{}' (one of {}, or all)", words[1], kind_names()));
    message["clear"] = words[1];
    add_flags(message, words, 2, {"receiver"}, "clear");
    return message.dump();
  }
  const std::optional<FaultKind> kind = parse_kind(command);
  if (!kind) {
    throw std::invalid_argument(
        fmt::format("ctl: unknown command '{}' (a fault kind: {}; or clear, status, send)", command, kind_names()));
  }
  std::vector<std::string_view> keys = parameters_of(*kind);
  keys.insert(keys.end(), kLiveCommonKeys.begin(), kLiveCommonKeys.end());
  message["fault"] = command;
  add_flags(message, words, 1, keys, command);
  return message.dump();
}

std::string control_flags_help() {
  std::string out = "KIND and its flags (--FLAG VALUE or --FLAG=VALUE; a key's unit may be left out: --ramp for --ramp-s):\n";
  for (const KindInfo& k : catalogue()) out += fmt::format("  {}: {}\n", k.name, flag_list(parameters_of(k.kind)));
  out += fmt::format("  every fault: {}\n", flag_list(std::vector<std::string_view>(kLiveCommonKeys.begin(), kLiveCommonKeys.end())));
  out += "  clear KIND|all [--receiver N]; status; send JSON; watch [--receiver N] [--count N] (one JSON line an epoch)\n";
  out += "Each parameter (the key of a [[fault]] table and of the JSON request):\n";
  std::vector<std::string_view> keys(kLiveCommonKeys.begin(), kLiveCommonKeys.end());
  for (const KindInfo& k : catalogue()) {
    for (const std::string_view key : parameters_of(k.kind)) {
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    }
  }
  std::sort(keys.begin() + static_cast<std::ptrdiff_t>(kLiveCommonKeys.size()), keys.end());
  for (const std::string_view key : keys) {
    if (const ParameterInfo* p = parameter_info(key)) out += fmt::format("  {}: {}\n", flags_of(key), p->help);
  }
  out.pop_back();  // CLI11 ends the footer's line
  return out;
}

}  // namespace gpsemu::faults
