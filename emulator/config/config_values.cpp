#include "emulator/config/config_values.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::config_values {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

bool to_double(const std::string& text, double& out) {
  const std::string t = trim(text);
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), out);
  return !t.empty() && ec == std::errc{} && ptr == t.data() + t.size() && std::isfinite(out);
}

}  // namespace

double parse_number(const std::string& key, const std::string& text, double min, double max) {
  double value = 0.0;
  if (!to_double(text, value)) {
    throw std::invalid_argument(fmt::format("{} expects a number from {} to {}, got '{}'", key, min, max, text));
  }
  if (value < min || value > max) {
    throw std::invalid_argument(fmt::format("{} must be from {} to {}, got {}", key, min, max, text));
  }
  return value;
}

std::vector<double> parse_list(const std::string& key, const std::string& text, std::size_t min_count,
                               std::size_t max_count) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    double value = 0.0;
    if (!to_double(item, value)) {
      throw std::invalid_argument(fmt::format("{}: '{}' is not a number (in '{}')", key, item, text));
    }
    out.push_back(value);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (out.size() < min_count || out.size() > max_count) {
    throw std::invalid_argument(min_count == max_count
        ? fmt::format("{} expects {} comma-separated numbers, got '{}'", key, min_count, text)
        : fmt::format("{} expects {} to {} comma-separated numbers, got '{}'", key, min_count, max_count, text));
  }
  return out;
}

bool parse_bool(const std::string& key, const std::string& text) {
  const std::string t = trim(text);
  if (t == "true" || t == "1" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "0" || t == "no" || t == "off") return false;
  throw std::invalid_argument(fmt::format("{} expects true or false, got '{}'", key, text));
}

std::uint64_t parse_uint(const std::string& key, const std::string& text) {
  const std::string t = trim(text);
  std::uint64_t value = 0;
  auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty() || ec != std::errc{} || ptr != t.data() + t.size()) {
    throw std::invalid_argument(fmt::format("{} expects a whole number >= 0, got '{}'", key, text));
  }
  return value;
}

std::string parse_choice(const std::string& key, const std::string& text,
                         std::initializer_list<const char*> accepted) {
  std::string list;
  for (const char* a : accepted) {
    if (text == a) return text;
    list += list.empty() ? a : fmt::format(", {}", a);
  }
  throw std::invalid_argument(fmt::format("{} must be one of {}, got '{}'", key, list, text));
}

std::string shorten_quoted(const std::string& message) {
  std::string out;
  std::size_t at = 0;
  while (at < message.size()) {
    const std::size_t open = message.find('\'', at);
    const std::size_t close = open == std::string::npos ? std::string::npos : message.find('\'', open + 1);
    if (close == std::string::npos) {
      out.append(message, at);
      break;
    }
    out.append(message, at, open + 1 - at);
    const std::size_t length = close - open - 1;
    out.append(message, open + 1, std::min(length, kMaxQuotedChars));
    if (length > kMaxQuotedChars) out += "...";
    out += '\'';
    at = close + 1;
  }
  if (out.size() > kMaxMessageChars) out = out.substr(0, kMaxMessageChars) + "...";
  return out;
}

noise::CgrwAxis parse_cgrw_axis(const std::string& key, const std::string& text) {
  const auto v = parse_list(key, text, 4, 4);
  if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0 && v[3] == 0.0) return {0.0, 0.0, 0.0, 0.0};  // axis off
  for (const double x : v) {
    if (!(x > 0.0)) throw std::invalid_argument(fmt::format("{}: every width must be > 0 metres (or all four 0: no noise on the axis), got '{}'", key, text));
  }
  return {v[0], v[1], v[2], v[3]};
}

}  // namespace gpsemu::config_values
