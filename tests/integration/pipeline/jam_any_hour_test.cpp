// A jam given as `leave = N` takes the same satellites away whatever the sky of the hour: through
// the real configuration and channel (receiver model, sky, faults, NMEA), at each of 24 hours of a
// day over ArduPilot SITL's home, `leave = 3` loses the fix in every epoch at full strength, and
// `leave = 6` leaves at most 6 used and 6 with a C/N0 in GSV (whether 6 of two or three systems
// still solve depends on the sky: one receiver clock each). A fixed `db = 25` keeps a fix at some
// hours (7 satellites at 20-24 dB-Hz): counted and printed (14 of 24 on 2026-11-28).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/run_settings.hpp"
#include "nmea/parse.hpp"
#include "tests/support/nmea_check.hpp"

namespace gpsemu {
namespace {
namespace jam_any_hour_test {

/// The sentences of one epoch's bytes, checked and split by nmea::parse_sentence.
std::vector<nmea::Sentence> sentences_of(const std::string& bytes) {
  std::vector<nmea::Sentence> out;
  for (const std::string& line : test::split_sentences(bytes).sentences) {
    if (auto s = nmea::parse_sentence(line); s.ok()) out.push_back(std::move(s).value());
  }
  return out;
}

struct HourResult {
  int epochs_jammed = 0;
  int with_fix = 0;       ///< GGA quality > 0 at full strength
  int most_used = 0;      ///< GGA's satellites used, largest
  int most_tracked = 0;   ///< GSV's satellites with a C/N0, largest
};

HourResult jam_at(int hour, const std::string& jam_keys) {
  const std::string start = fmt::format("2026-11-28T{:02d}:00:00Z", hour);
  const std::string toml = fmt::format("[[fault]]\nkind = \"jam\"\nat = 2\nduration = 6\n{}\n", jam_keys);
  const RawOptions cli{{"receiver", {"ublox-m8n"}},       {"sentences", {"GGA,GSA,GSV"}},
                       {"start-time", {start}},           {"origin", {"-35.363261,149.165230,584"}},
                       {"rate", {"1"}},                   {"duration", {"8"}},
                       {"noise", {"none"}},               {"log-level", {"warn"}}};
  const Config config = build_config_from_text(toml, "jam.toml", cli);
  RunSettings run = run_settings(config);
  const UtcNs t0 = parse_iso8601_utc(start);
  Channel channel(run.receivers.at(0).channel, t0);
  const sources::Truth at_rest{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, std::nullopt, {}};
  HourResult r;
  for (int k = 0; k < 8; ++k) {
    (void)channel.step(t0 + std::chrono::seconds(k), at_rest);
    if (k < 2) continue;  // before the jam
    int tracked = 0;
    std::optional<std::vector<std::string>> gga;
    for (const nmea::Sentence& s : sentences_of(channel.bytes())) {
      if (s.type == "GGA") gga = s.fields;
      // GSV: total, number, in view, then (id, elevation, azimuth, C/N0) x up to 4 [, signal id].
      if (s.type == "GSV") {
        for (std::size_t at = 3; at + 3 < s.fields.size(); at += 4) tracked += s.fields[at + 3].empty() ? 0 : 1;
      }
    }
    if (!gga || gga->size() < 7) continue;
    ++r.epochs_jammed;
    if (!(*gga)[5].empty() && (*gga)[5] != "0") ++r.with_fix;
    r.most_used = std::max(r.most_used, (*gga)[6].empty() ? 0 : std::stoi((*gga)[6]));
    r.most_tracked = std::max(r.most_tracked, tracked);
  }
  return r;
}

TEST(JamAnyHour, LeavingThreeSatellitesLosesTheFixAtEveryHour) {
  int fixed_db_hours_with_fix = 0;
  for (int hour = 0; hour < 24; ++hour) {
    const HourResult leave3 = jam_at(hour, "leave = 3");
    EXPECT_EQ(leave3.epochs_jammed, 6) << "hour " << hour;
    EXPECT_EQ(leave3.with_fix, 0) << "hour " << hour << ": a fix under a jam leaving 3 satellites";
    EXPECT_LE(leave3.most_tracked, 3) << "hour " << hour;
    const HourResult leave6 = jam_at(hour, "leave = 6");
    EXPECT_GE(leave6.epochs_jammed, 6) << "hour " << hour;  // a fix or not: 6 of three systems may not solve
    EXPECT_LE(leave6.most_used, 6) << "hour " << hour;
    EXPECT_LE(leave6.most_tracked, 6) << "hour " << hour;
    if (jam_at(hour, "db = 25").with_fix > 0) ++fixed_db_hours_with_fix;
  }
  std::printf("a fixed 25 dB jam kept a fix at %d of 24 hours\n", fixed_db_hours_with_fix);
}

}  // namespace jam_any_hour_test
}  // namespace
}  // namespace gpsemu
