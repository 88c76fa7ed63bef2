// libFuzzer target for the two readers of recorded NMEA logs, which take any bytes:
//  - `gpsemu replay LOG` (emulator/replay/replay_log.hpp): parse_replay_log() cuts the log into
//    epochs; then select_range() with --from/--to positions taken from the input, and
//    retime_epoch() of the selected epochs;
//  - `gpsemu calibrate LOG` (emulator/calibration/receiver_log.hpp): read_receiver_log() and
//    to_enu_series().
// Checks: every epoch holds sentences whose raw bytes are its bytes, each raw sentence starts with
// '$' and parses back to the fields kept; the sentence count is StreamReader's; log times of
// timed epochs only go back where a step back was counted; a retimed epoch is the same sentences
// (types and field counts) with valid checksums, its valid time fields are the new time's and its
// empty or malformed ones are as recorded; the calibration fixes are in strictly increasing time with finite, in-range positions; the series
// has one sample per grid epoch, NaN exactly for the missing ones.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

#include "emulator/calibration/receiver_log.hpp"
#include "emulator/replay/replay_log.hpp"
#include "emulator/model/time.hpp"
#include "fuzz_check.hpp"
#include "nmea/parse.hpp"

namespace {

using namespace gpsemu;
using namespace gpsemu::replay;

/// The raw sentence without its line ending.
std::string_view without_ending(std::string_view raw) {
  while (!raw.empty() && (raw.back() == '\r' || raw.back() == '\n')) raw.remove_suffix(1);
  return raw;
}

void check_replay(std::string_view bytes) {
  const ReplayLog log = parse_replay_log(bytes);
  std::uint64_t sentences = 0;
  for (const LogEpoch& epoch : log.epochs) {
    GPSEMU_FUZZ_CHECK(!epoch.sentences.empty());
    std::string joined;
    for (const LogSentence& s : epoch.sentences) {
      GPSEMU_FUZZ_CHECK(!s.raw.empty() && s.raw.front() == '$');
      const auto again = nmea::parse_sentence(without_ending(s.raw));
      GPSEMU_FUZZ_CHECK(again.ok() && again->fields == s.parsed.fields && again->type == s.parsed.type &&
                        again->talker == s.parsed.talker);
      if (s.time_of_day) GPSEMU_FUZZ_CHECK(*s.time_of_day >= std::chrono::nanoseconds::zero() &&
                                           *s.time_of_day < std::chrono::hours(24) + std::chrono::seconds(1));
      joined += s.raw;
      ++sentences;
    }
    GPSEMU_FUZZ_CHECK(joined == epoch.bytes);
  }
  GPSEMU_FUZZ_CHECK(sentences == log.counts.stream.sentences_ok);
  GPSEMU_FUZZ_CHECK(log.period > std::chrono::nanoseconds::zero());
  std::uint64_t back = 0;
  const LogEpoch* previous = nullptr;
  for (const LogEpoch& epoch : log.epochs) {
    if (!epoch.time_of_day) continue;
    if (previous && epoch.log_time < previous->log_time) ++back;
    previous = &epoch;
  }
  GPSEMU_FUZZ_CHECK(back <= log.counts.steps_back);
  if (log.epochs.empty() || bytes.size() < 2) return;

  // --from/--to from the first two bytes: nothing, an index, or a time of day.
  auto position = [&](unsigned char b) -> std::optional<LogPosition> {
    switch (b % 3) {
      case 0: return std::nullopt;
      case 1: return LogPosition{static_cast<std::int64_t>(b / 3) - 2};
      default: return LogPosition{std::chrono::nanoseconds(std::chrono::minutes(b * 7))};
    }
  };
  EpochRange range;
  try {
    range = select_range(log, position(static_cast<unsigned char>(bytes[0])),
                         position(static_cast<unsigned char>(bytes[1])));
  } catch (const std::invalid_argument&) {
    return;
  }
  GPSEMU_FUZZ_CHECK(range.first <= range.last && range.last < log.epochs.size());
  const UtcNs base = parse_iso8601_utc("2024-02-28T23:59:59.995Z");
  const std::size_t last = std::min(range.last, range.first + 8);  // bounded work per input
  for (std::size_t i = range.first; i <= last; ++i) {
    const LogEpoch& epoch = log.epochs[i];
    const UtcNs when = base + (epoch.log_time - log.epochs[range.first].log_time);
    const std::string retimed = retime_epoch(epoch, when);
    nmea::StreamReader reader;
    std::vector<nmea::Sentence> out = reader.feed(retimed);
    if (auto tail = reader.finish()) out.push_back(std::move(*tail));
    GPSEMU_FUZZ_CHECK(reader.stats().bad_checksum == 0 && out.size() == epoch.sentences.size());
    for (std::size_t k = 0; k < out.size(); ++k) {
      const nmea::Sentence& before = epoch.sentences[k].parsed;
      GPSEMU_FUZZ_CHECK(out[k].talker == before.talker && out[k].type == before.type &&
                        out[k].fields.size() == before.fields.size());
      const auto t = time_field_index(before);
      if (t && *t < before.fields.size() && !epoch.sentences[k].time_of_day) {
        GPSEMU_FUZZ_CHECK(out[k].fields[*t] == before.fields[*t]);  // empty or malformed: as recorded
      } else if (t && *t < before.fields.size()) {
        // The new time of day, rounded to the decimals the field had.
        const auto tod = parse_time_of_day(out[k].fields[*t]);
        GPSEMU_FUZZ_CHECK(tod.has_value());
        const std::string& old_field = before.fields[*t];
        const auto point = old_field.find('.');
        const std::size_t decimals = point == std::string::npos ? 0 : std::min<std::size_t>(9, old_field.size() - point - 1);
        std::int64_t half_unit_ns = 500'000'000;
        for (std::size_t d = 0; d < decimals; ++d) half_unit_ns /= 10;
        const std::int64_t day_ns = std::chrono::nanoseconds(std::chrono::hours(24)).count();
        const std::int64_t want = (when.time_since_epoch().count() % day_ns + day_ns) % day_ns;
        const std::int64_t diff = ((tod->count() - want) % day_ns + day_ns) % day_ns;
        GPSEMU_FUZZ_CHECK(diff <= half_unit_ns || diff >= day_ns - half_unit_ns);
      }
    }
  }
}

void check_calibration(std::string_view bytes) {
  calibration::ReceiverLog log = calibration::read_receiver_log(bytes);
  for (std::size_t i = 0; i < log.fixes.size(); ++i) {
    const auto& f = log.fixes[i];
    GPSEMU_FUZZ_CHECK(std::isfinite(f.time_s) && f.time_s >= 0.0);
    if (i > 0) GPSEMU_FUZZ_CHECK(f.time_s > log.fixes[i - 1].time_s);
    GPSEMU_FUZZ_CHECK(std::abs(f.position.lat_deg) <= 90.0 && std::abs(f.position.lon_deg) <= 180.0 &&
                      std::isfinite(f.position.alt_m));
  }
  // A series over more than an hour of log time is up to 10 million samples an axis (refused
  // above that; calibration_log_test covers it): not worth its time per fuzz input.
  if (!log.fixes.empty() && log.fixes.back().time_s > 3600.0) return;
  calibration::EnuSeries series;
  try {
    series = calibration::to_enu_series(log);
  } catch (const std::invalid_argument& e) {
    GPSEMU_FUZZ_CHECK(log.fixes.size() < 16 || std::string_view(e.what()).find("at most") != std::string_view::npos);
    return;
  }
  GPSEMU_FUZZ_CHECK(series.size() >= 1 && series.rate_hz > 0.0);
  std::size_t present = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const bool gap = std::isnan(series.axis_m[0][k]);
    GPSEMU_FUZZ_CHECK(gap == std::isnan(series.axis_m[1][k]) && gap == std::isnan(series.axis_m[2][k]));
    if (!gap) {
      ++present;
      GPSEMU_FUZZ_CHECK(std::isfinite(series.axis_m[0][k]) && std::isfinite(series.axis_m[1][k]) &&
                        std::isfinite(series.axis_m[2][k]));
    }
  }
  GPSEMU_FUZZ_CHECK(present + log.counts.missing_epochs == series.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  check_replay(bytes);
  check_calibration(bytes);
  return 0;
}
