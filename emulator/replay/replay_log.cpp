#include "emulator/replay/replay_log.hpp"

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "nmea/sentences.hpp"
#include "transport/posix/errors.hpp"

namespace gpsemu::replay {
namespace {

using std::chrono::nanoseconds;
constexpr nanoseconds kDay = std::chrono::hours(24);
constexpr nanoseconds kHalfDay = std::chrono::hours(12);

bool is_digit(char c) { return c >= '0' && c <= '9'; }

/// Positive remainder of a by b.
nanoseconds mod(nanoseconds a, nanoseconds b) {
  const nanoseconds r = a % b;
  return r < nanoseconds::zero() ? r + b : r;
}

/// Talker + type, e.g. "GPGGA" (an epoch holds each time-bearing address once).
std::string address(const nmea::Sentence& s) { return s.talker + s.type; }

/// The epoch being assembled. Past kMaxEpochSentences or kMaxEpochBytes it is oversized: its
/// sentences are let go and only counted, so memory stays bounded whatever the log holds.
struct Builder {
  LogEpoch epoch;
  std::vector<std::string> addresses;  ///< distinct addresses seen in the epoch
  bool empty_time_field = false;  ///< holds a time-bearing sentence whose time is empty
  std::uint64_t sentences = 0;    ///< sentences given to the epoch, kept or not

  [[nodiscard]] bool empty() const { return sentences == 0; }
  [[nodiscard]] bool oversized() const { return sentences > epoch.sentences.size(); }
  [[nodiscard]] bool has(const std::string& a) const {
    return std::find(addresses.begin(), addresses.end(), a) != addresses.end();
  }
  void add(LogSentence s) {
    if (std::string a = address(s.parsed); !has(a)) addresses.push_back(std::move(a));
    ++sentences;
    if (sentences > kMaxEpochSentences || epoch.bytes.size() + s.raw.size() > kMaxEpochBytes) {
      epoch.sentences = {};  // oversized: kept no longer
      epoch.bytes = {};
      return;
    }
    epoch.bytes += s.raw;
    epoch.sentences.push_back(std::move(s));
  }
};

/// Cuts sentences into epochs (rules in replay_log.hpp).
class EpochCutter {
 public:
  EpochCutter(std::vector<LogEpoch>& out, LogCounts& counts) : out_(out), counts_(counts) {}

  void add(LogSentence s) {
    const bool time_bearing = time_field_index(s.parsed).has_value();
    if (s.time_of_day) {
      const auto tod = *s.time_of_day;
      if (current_.empty()) {
        current_.epoch.time_of_day = tod;
      } else if (current_.epoch.time_of_day) {
        if (*current_.epoch.time_of_day != tod) {
          close();
          current_.epoch.time_of_day = tod;
        }
      } else if (current_.empty_time_field) {
        close();  // a no-time epoch, then the first timed one
        current_.epoch.time_of_day = tod;
      } else {
        current_.epoch.time_of_day = tod;  // leading GSA/GSV... belong to this epoch
      }
    } else if (time_bearing) {
      if (current_.has(address(s.parsed))) close();
      current_.empty_time_field = true;
    }
    current_.add(std::move(s));
  }

  void close() {
    if (current_.oversized()) {
      ++counts_.oversized_epochs;
      counts_.oversized_sentences += current_.sentences;
    } else if (!current_.empty()) {
      out_.push_back(std::move(current_.epoch));
    }
    current_ = Builder{};
  }

 private:
  std::vector<LogEpoch>& out_;
  LogCounts& counts_;
  Builder current_;
};

/// Places every epoch on the log's timeline and counts rollovers, steps back, gaps.
void place_in_time(ReplayLog& log) {
  auto& epochs = log.epochs;
  LogCounts& n = log.counts;
  // Timed epochs: time of day plus whole days.
  std::int64_t day = 0;
  std::optional<nanoseconds> previous;
  std::vector<nanoseconds> spacings;
  for (auto& e : epochs) {
    if (!e.time_of_day) {
      ++n.untimed_epochs;
      continue;
    }
    const nanoseconds tod = *e.time_of_day;
    if (previous) {
      if (tod < *previous - kHalfDay) {
        ++day;
        ++n.rollovers;
      } else if (tod > *previous + kHalfDay) {
        --day;  // back across midnight
        ++n.steps_back;
      } else if (tod < *previous) {
        ++n.steps_back;
      }
    }
    e.log_time = day * kDay + tod;
    previous = tod;
  }
  // Nominal period: the median positive spacing of consecutive timed epochs.
  const LogEpoch* last_timed = nullptr;
  for (const auto& e : epochs) {
    if (!e.time_of_day) continue;
    if (last_timed && e.log_time > last_timed->log_time) spacings.push_back(e.log_time - last_timed->log_time);
    last_timed = &e;
  }
  if (!spacings.empty()) {
    std::nth_element(spacings.begin(), spacings.begin() + static_cast<std::ptrdiff_t>((spacings.size() - 1) / 2),
                     spacings.end());
    log.period = spacings[(spacings.size() - 1) / 2];  // the lower median
  }
  // Gaps between consecutive timed epochs.
  last_timed = nullptr;
  for (const auto& e : epochs) {
    if (!e.time_of_day) continue;
    if (last_timed) {
      const nanoseconds d = e.log_time - last_timed->log_time;
      if (d * 2 > log.period * 3) {
        ++n.gaps;
        n.longest_gap = std::max(n.longest_gap, d);
      }
    }
    last_timed = &e;
  }
  // Epochs without a time: one period after the previous epoch, or before the first timed one.
  const auto first_timed = std::find_if(epochs.begin(), epochs.end(), [](const LogEpoch& e) { return e.time_of_day.has_value(); });
  const auto leading = first_timed - epochs.begin();
  const nanoseconds start = first_timed == epochs.end() ? nanoseconds::zero() : first_timed->log_time - leading * log.period;
  for (std::ptrdiff_t i = 0; i < leading; ++i) epochs[static_cast<std::size_t>(i)].log_time = start + i * log.period;
  for (auto it = first_timed; it != epochs.end(); ++it) {
    if (!it->time_of_day) it->log_time = std::prev(it)->log_time + log.period;
  }
}

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
  ReplayLog log;
  nmea::StreamReader reader;
  EpochCutter cutter(log.epochs, log.counts);
  std::size_t dollar = 0;  // where the candidate sentence started
  auto take = [&](nmea::Sentence&& parsed, std::size_t end, std::size_t ending) {
    LogSentence s;
    s.raw.assign(bytes.substr(dollar, end - dollar + ending));
    s.parsed = std::move(parsed);
    if (const auto i = time_field_index(s.parsed); i && *i < s.parsed.fields.size() && !s.parsed.fields[*i].empty()) {
      s.time_of_day = parse_time_of_day(s.parsed.fields[*i]);
      if (!s.time_of_day) ++log.counts.bad_time_fields;
    }
    cutter.add(std::move(s));
  };
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (bytes[i] == '$') dollar = i;
    auto done = reader.feed(bytes.substr(i, 1));
    if (done.empty()) continue;
    // A sentence ends at this CR or LF; a CR LF pair is its line ending.
    const std::size_t ending = (bytes[i] == '\r' && i + 1 < bytes.size() && bytes[i + 1] == '\n') ? 2 : 1;
    take(std::move(done.front()), i, ending);
  }
  if (auto last = reader.finish()) take(std::move(*last), bytes.size(), 0);
  cutter.close();
  log.counts.stream = reader.stats();
  place_in_time(log);
  return log;
}

ReplayLog read_replay_log(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot open NMEA log '{}': {}", path.string(), posix::errno_text(errno)));
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw std::runtime_error(fmt::format("cannot read NMEA log '{}'", path.string()));
  const std::string bytes = std::move(content).str();
  ReplayLog log = parse_replay_log(bytes);
  if (log.epochs.empty() && log.counts.oversized_epochs > 0) {
    throw std::runtime_error(fmt::format(
        "NMEA log '{}' has no epoch to send: {} oversized epochs ({} sentences) skipped; an epoch may have at most {} "
        "sentences and {} bytes", path.string(), log.counts.oversized_epochs, log.counts.oversized_sentences,
        kMaxEpochSentences, kMaxEpochBytes));
  }
  if (log.epochs.empty()) {
    const auto& s = log.counts.stream;
    throw std::runtime_error(fmt::format(
        "NMEA log '{}' holds no valid NMEA sentence ({} bytes: {} bad checksums, {} malformed, {} binary/garbage "
        "bytes, {} comment lines)", path.string(), bytes.size(), s.bad_checksum, s.malformed, s.garbage_bytes,
        s.comment_lines));
  }
  return log;
}

EpochRange select_range(const ReplayLog& log, const std::optional<LogPosition>& from,
                        const std::optional<LogPosition>& to) {
  const auto& e = log.epochs;
  const std::size_t n = e.size();
  auto index_of = [&](const char* key, const LogPosition& p) {
    const auto i = std::get<std::int64_t>(p.value);
    if (i < 0 || static_cast<std::size_t>(i) >= n) {
      throw std::invalid_argument(fmt::format("{}: epoch {} is past the end: the log has {} epochs (0..{})", key, i, n,
                                              n - 1));
    }
    return static_cast<std::size_t>(i);
  };
  // A time of day as a point on the log's timeline: its first occurrence at or after `ref`.
  auto on_timeline = [](nanoseconds ref, const LogPosition& p) {
    return ref + mod(std::get<nanoseconds>(p.value) - mod(ref, kDay), kDay);
  };
  EpochRange r{0, n - 1};
  nanoseconds from_time = e.front().log_time;  // where --to's time of day is looked for from
  if (from) {
    if (from->is_time_of_day()) {
      const nanoseconds t = on_timeline(e.front().log_time, *from);
      from_time = t;
      const auto it = std::find_if(e.begin(), e.end(), [&](const LogEpoch& x) { return x.log_time >= t; });
      if (it == e.end()) {
        throw std::invalid_argument(fmt::format("from: {}: no epoch at or after it in the log (its times run from {} "
                                                "to {})", to_string(*from),
                                                to_string(LogPosition{mod(e.front().log_time, kDay)}),
                                                to_string(LogPosition{mod(e.back().log_time, kDay)})));
      }
      r.first = static_cast<std::size_t>(it - e.begin());
    } else {
      r.first = index_of("from", *from);
      from_time = e[r.first].log_time;
    }
  }
  if (to) {
    if (to->is_time_of_day()) {
      const nanoseconds t = on_timeline(from_time, *to);
      std::size_t j = r.first;
      while (j < n && e[j].log_time <= t) ++j;
      if (j == r.first) {
        throw std::invalid_argument(fmt::format("to: {}: no epoch from {} up to it", to_string(*to),
                                                from ? to_string(*from) : "the start"));
      }
      r.last = j - 1;
    } else {
      r.last = index_of("to", *to);
    }
  }
  if (r.last < r.first) {
    throw std::invalid_argument(fmt::format("to: epoch {} comes before the first one selected (epoch {})", r.last,
                                            r.first));
  }
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
    if (s.parsed.talker != "P" && s.parsed.type == "RMC" && fields.size() > 8 && !fields[8].empty()) {
      fields[8] = fmt::format("{:02}{:02}{:02}", dd, mm, yyyy % 100);
    }
    if (s.parsed.talker != "P" && s.parsed.type == "ZDA" && fields.size() > 3) {
      if (!fields[1].empty()) fields[1] = fmt::format("{:02}", dd);
      if (!fields[2].empty()) fields[2] = fmt::format("{:02}", mm);
      if (!fields[3].empty()) fields[3] = fmt::format("{:04}", yyyy);
    }
    std::string body = address(s.parsed);
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
