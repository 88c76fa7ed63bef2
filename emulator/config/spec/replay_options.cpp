#include "emulator/config/spec/replay_options.hpp"

#include <charconv>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu::replay {
namespace {

/// Digits only, at most `max_digits`; nothing on failure.
std::optional<std::int64_t> whole(std::string_view s, std::size_t max_digits) {
  if (s.empty() || s.size() > max_digits || s.find_first_not_of("0123456789") != std::string_view::npos) {
    return std::nullopt;
  }
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc{} || ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

LogPosition parse_log_position(const std::string& key, const std::string& text) {
  const auto bad = [&] {
    return std::invalid_argument(fmt::format("{}: expected a time of day hh:mm:ss[.ss] (UTC, as in the log) or an "
                                             "epoch index 0, 1, ..., got '{}'", key, text));
  };
  if (text.find(':') == std::string::npos) {
    const auto index = whole(text, 12);
    if (!index) throw bad();
    return {*index};
  }
  // hh:mm:ss[.fraction]
  if (text.size() < 8 || text[2] != ':' || text[5] != ':') throw bad();
  const auto h = whole(std::string_view(text).substr(0, 2), 2);
  const auto m = whole(std::string_view(text).substr(3, 2), 2);
  const auto s = whole(std::string_view(text).substr(6, 2), 2);
  if (!h || !m || !s || *h > 23 || *m > 59 || *s > 59) throw bad();
  std::int64_t ns = ((*h * 60 + *m) * 60 + *s) * 1'000'000'000;
  if (text.size() > 8) {
    if (text[8] != '.' || text.size() == 9 || text.size() > 18) throw bad();
    const auto frac = whole(std::string_view(text).substr(9), 9);
    if (!frac) throw bad();
    std::int64_t scale = 1;
    for (std::size_t i = text.size() - 9; i < 9; ++i) scale *= 10;
    ns += *frac * scale;
  }
  return {std::chrono::nanoseconds{ns}};
}

std::string to_string(const LogPosition& position) {
  if (const auto* index = std::get_if<std::int64_t>(&position.value)) return fmt::format("epoch {}", *index);
  const auto ns = std::get<std::chrono::nanoseconds>(position.value).count();
  const std::int64_t ms = ns / 1'000'000;
  return fmt::format("{:02}:{:02}:{:02}.{:03}", ms / 3'600'000, ms / 60'000 % 60, ms / 1000 % 60, ms % 1000);
}

}  // namespace gpsemu::replay
