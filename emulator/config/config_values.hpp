// Parsing of option values (numbers with ranges, lists, booleans, choices) with messages that say
// what was expected. Shared by the command line and the config file.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "emulator/model/noise/noise_model.hpp"

namespace gpsemu::config_values {

/// A finite number in [min, max]; throws std::invalid_argument naming `key`, the range and `text`.
[[nodiscard]] double parse_number(const std::string& key, const std::string& text, double min, double max);
/// Comma-separated numbers, between `min_count` and `max_count` of them.
[[nodiscard]] std::vector<double> parse_list(const std::string& key, const std::string& text,
                                             std::size_t min_count, std::size_t max_count);
[[nodiscard]] bool parse_bool(const std::string& key, const std::string& text);
[[nodiscard]] std::uint64_t parse_uint(const std::string& key, const std::string& text);
[[nodiscard]] std::string parse_choice(const std::string& key, const std::string& text,
                                       std::initializer_list<const char*> accepted);

/// A cgrw axis "W,W1,W2,S2": four widths > 0 metres, or all four 0 (no noise on the axis).
[[nodiscard]] noise::CgrwAxis parse_cgrw_axis(const std::string& key, const std::string& text);

/// Longest quoted value an error message shows (characters); longer ones end in "...".
inline constexpr std::size_t kMaxQuotedChars = 80;
/// Longest error message (characters): whatever a value holds, the message stays one short line.
inline constexpr std::size_t kMaxMessageChars = 1000;
/// `message` with every '...'-quoted part longer than kMaxQuotedChars cut to that many characters
/// and "...", and the whole cut to kMaxMessageChars: a 100 MB value is not echoed back.
[[nodiscard]] std::string shorten_quoted(const std::string& message);

}  // namespace gpsemu::config_values
