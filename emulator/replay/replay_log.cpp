#include "emulator/replay/replay_log.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/replay/epoch_range.hpp"
#include "emulator/replay/log_stream.hpp"
#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::replay {
namespace {

using std::chrono::nanoseconds;

bool is_digit(char c) { return c >= '0' && c <= '9'; }

/// Formats a time of day as hhmmss[.d...] with `decimals` decimals (`dot`: a '.' even with none).
std::string format_time_of_day(nanoseconds tod, int decimals, bool dot) {
  std::int64_t unit = 1'000'000'000;
  for (int i = 0; i < decimals; ++i) unit /= 10;
  const std::int64_t units = (tod.count() + unit / 2) / unit;  // rounded; tod < 24 h already
  const std::int64_t per_second = 1'000'000'000 / unit;
  const std::int64_t s = units / per_second;
  std::string out = fmt::format("{:02}{:02}{:02}", s / 3600 % 24, s / 60 % 60, s % 60);
  if (dot || decimals > 0) out += '.';
  if (decimals > 0) out += fmt::format("{:0{}}", units % per_second, decimals);
  return out;
}

}  // namespace

std::optional<std::size_t> time_field_index(const nmea::Sentence& s) {
  if (s.talker == "P") return std::nullopt;  // proprietary: layouts of their own
  if (s.type == "GLL") return 4;
  if (s.type == "GGA" || s.type == "RMC" || s.type == "ZDA" || s.type == "GST" || s.type == "GNS" ||
      s.type == "GBS" || s.type == "GRS") {
    return 0;
  }
  return std::nullopt;
}

std::optional<nanoseconds> parse_time_of_day(std::string_view f) {
  if (f.size() < 6 || !std::all_of(f.begin(), f.begin() + 6, is_digit)) return std::nullopt;
  const int h = (f[0] - '0') * 10 + (f[1] - '0');
  const int m = (f[2] - '0') * 10 + (f[3] - '0');
  const int s = (f[4] - '0') * 10 + (f[5] - '0');
  if (h > 23 || m > 59 || s > 60) return std::nullopt;
  std::int64_t ns = ((h * 60LL + m) * 60 + s) * 1'000'000'000;
  if (f.size() > 6) {
    if (f[6] != '.' || f.size() > 16 || !std::all_of(f.begin() + 7, f.end(), is_digit)) return std::nullopt;
    std::int64_t scale = 100'000'000;
    for (std::size_t i = 7; i < f.size(); ++i, scale /= 10) ns += (f[i] - '0') * scale;
  }
  return nanoseconds{ns};
}

ReplayLog parse_replay_log(std::string_view bytes) {
  LogStream stream(bytes, "log");
  ReplayLog log;
  for (LogEpoch e; stream.pop(&e);) log.epochs.push_back(std::move(e));
  log.counts = stream.counts();
  log.period = stream.period();
  return log;
}

EpochRange select_range(const ReplayLog& log, const std::optional<LogPosition>& from,
                        const std::optional<LogPosition>& to) {
  const auto& e = log.epochs;
  RangeCursor cursor(from, to, e.empty() ? std::chrono::nanoseconds::zero() : e.front().log_time);
  EpochRange r;
  std::size_t i = 0;
  for (; i < e.size(); ++i) {
    const auto place = cursor.place(i, e[i]);
    if (place == RangeCursor::Place::after) break;
    if (place == RangeCursor::Place::in) r.last = i;
  }
  if (i == e.size()) cursor.at_end(e.size(), e.empty() ? std::chrono::nanoseconds::zero() : e.back().log_time);
  r.first = static_cast<std::size_t>(*cursor.first());
  return r;
}

std::string retime_epoch(const LogEpoch& epoch, UtcNs time) {
  using namespace std::chrono;
  std::string out;
  out.reserve(epoch.bytes.size() + 16);
  for (const LogSentence& s : epoch.sentences) {
    const auto time_index = time_field_index(s.parsed);
    std::vector<std::string> fields = s.parsed.fields;
    // The rounded time decides the date too (23:59:59.996 rounds into the next day).
    int decimals = 0;
    bool dot = false;
    UtcNs rounded = time;
    // Only a time the log held is rewritten: a malformed time field is sent as recorded (rewritten,
    // "1." would grow to "120000." and could push the sentence over the parser's length limit).
    if (s.time_of_day && time_index && *time_index < fields.size()) {
      const std::string& f = fields[*time_index];
      const auto point = f.find('.');
      dot = point != std::string::npos;
      decimals = dot ? std::min<int>(9, static_cast<int>(f.size() - point - 1)) : 0;
      std::int64_t unit = 1'000'000'000;
      for (int i = 0; i < decimals; ++i) unit /= 10;
      const auto ns = time.time_since_epoch().count();
      rounded = UtcNs{nanoseconds{(ns >= 0 ? (ns + unit / 2) / unit : (ns - unit / 2) / unit) * unit}};
      fields[*time_index] = format_time_of_day(rounded - floor<days>(rounded), decimals, dot);
    }
    const year_month_day date{floor<days>(rounded)};
    const unsigned dd = static_cast<unsigned>(date.day()), mm = static_cast<unsigned>(date.month());
    const int yyyy = static_cast<int>(date.year());
    // Likewise only a date the log held in its own width (ddmmyy, dd, mm, yyyy) is rewritten: a
    // 1-character field would grow to 6 and could push the sentence over the parser's limit.
    const auto digits = [](const std::string& f, std::size_t n) { return f.size() == n && nmea::all_digits(f); };
    if (s.parsed.talker != "P" && s.parsed.type == "RMC" && fields.size() > 8 && digits(fields[8], 6)) {
      fields[8] = fmt::format("{:02}{:02}{:02}", dd, mm, yyyy % 100);
    }
    if (s.parsed.talker != "P" && s.parsed.type == "ZDA" && fields.size() > 3) {
      if (digits(fields[1], 2)) fields[1] = fmt::format("{:02}", dd);
      if (digits(fields[2], 2)) fields[2] = fmt::format("{:02}", mm);
      if (digits(fields[3], 4)) fields[3] = fmt::format("{:04}", yyyy);
    }
    std::string body = s.parsed.talker + s.parsed.type;
    for (const auto& f : fields) {
      body += ',';
      body += f;
    }
    const auto star = s.raw.find('*');
    const std::string_view ending =
        star == std::string::npos || star + 3 > s.raw.size() ? std::string_view{} : std::string_view(s.raw).substr(star + 3);
    out += fmt::format("${}*{:02X}", body, nmea::checksum(body));
    out += ending;
  }
  return out;
}

}  // namespace gpsemu::replay
