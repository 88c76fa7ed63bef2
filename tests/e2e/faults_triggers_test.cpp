// The triggers through the binary (--fast, a fixed start): a truth on sim:line at 20 m/s east
// enters a circle (an outage while inside), a polygon (a jump while inside) and meets an at_utc
// (rtk-fixed at a UTC second); a jam ramps out over its ramp_out_s. Each shows in the GGA at
// exactly the epochs the truth was inside, or at the UTC second.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include <fmt/format.h>

#include "emulator/model/geo.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_triggers_test {

const Geodetic kOrigin{43.0725, -89.4125, 260.0};  // gpsemu's default origin; sim:line starts there

struct Gga {
  int quality = -1, satellites = -1;
  double lat_deg = NAN, lon_deg = NAN;
};

std::map<int, Gga> by_second(const std::string& text) {
  std::map<int, Gga> out;
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(text)) {
    if (s.type != "GGA") continue;
    const auto gga = nmea::parse_gga(s);
    if (!gga.ok() || !gga->time_of_day) continue;
    out[static_cast<int>(gga->time_of_day->count() / 1000)] = {static_cast<int>(gga->quality),
                                                                gga->satellites.value_or(-1), gga->lat_deg.value_or(NAN),
                                                                gga->lon_deg.value_or(NAN)};
  }
  return out;
}

TEST(FaultsTriggers, AreasAndUtcStartFaultsAtTheEpochsTheTruthIsInsideOrTheTimeComes) {
  const LocalFrame frame(kOrigin);
  const Geodetic circle = frame.to_geodetic({100.0, 0.0, 0.0});  // the truth is there at 5 s
  const Geodetic sw = frame.to_geodetic({170.0, -50.0, 0.0}), ne = frame.to_geodetic({230.0, 50.0, 0.0});
  const std::string scenario = fmt::format(
      "[[fault]]\nkind = \"outage\"\nwhere = \"circle:{:.9f},{:.9f},30\"\n"
      "[[fault]]\nkind = \"jump\"\nnorth_m = 500\nwhere = \"polygon:{:.9f},{:.9f};{:.9f},{:.9f};{:.9f},{:.9f};{:.9f},{:.9f}\"\n"
      "[[fault]]\nkind = \"fix-quality\"\nquality = \"rtk-fixed\"\nat_utc = \"2024-05-01T00:00:13Z\"\nduration = 1\n"
      "[[fault]]\nkind = \"jam\"\nat = 15\nduration = 1\ndb = 40\nramp_out_s = 2\n",
      circle.lat_deg, circle.lon_deg, sw.lat_deg, sw.lon_deg, sw.lat_deg, ne.lon_deg, ne.lat_deg, ne.lon_deg, ne.lat_deg,
      sw.lon_deg);
  const auto dir = test::scratch_dir("faults", "triggers");
  const auto file = test::write_file(dir / "triggers.toml", scenario);
  const test::Result r = test::run_fast(GPSEMU_BINARY, {"--duration", "19", "--source", "sim:line", "--sim-speed", "20",
                                                        "--seed", "4", "--scenario", file.string(), "--log-level", "info"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::map<int, Gga> e = by_second(r.out);
  ASSERT_EQ(e.size(), 19u);
  // The circle: truth 70..130 m east, epochs 4, 5, 6 (80, 100, 120 m).
  for (int k = 0; k < 19; ++k) {
    if (k == 17) continue;  // the jam's fade at half strength (below)
    const bool outage = k >= 4 && k <= 6;
    const bool jammed = k >= 15 && k <= 16;  // at 15, and at 16 its fade's start: 40 dB down, tracking lost
    EXPECT_EQ(e.at(k).quality == 0, outage || jammed) << k;
  }
  // The polygon: 170..230 m east, epochs 9, 10, 11: 500 m north while inside (the noise: a metre).
  const auto north_m = [&](int k) { return frame.to_enu({e.at(k).lat_deg, e.at(k).lon_deg, 260.0}).north_m; };
  for (const int k : {8, 12}) EXPECT_NEAR(north_m(k), 0.0, 5.0) << k;
  for (const int k : {9, 10, 11}) EXPECT_NEAR(north_m(k), 500.0, 5.0) << k;
  EXPECT_TRUE(test::contains(r.err, "fault jump east_m=0 north_m=500 up_m=0 where polygon:")) << r.err;
  EXPECT_TRUE(test::contains(r.err, "starts at epoch 2024-05-01T00:00:09.000Z")) << r.err;
  EXPECT_TRUE(test::contains(r.err, "fault jump ends at epoch 2024-05-01T00:00:12.000Z")) << r.err;
  // at_utc: rtk-fixed (4) at 13 s only.
  EXPECT_EQ(e.at(12).quality, 1);
  EXPECT_EQ(e.at(13).quality, 4);
  EXPECT_EQ(e.at(14).quality, 1);
  // The jam's ramp out over 2 s from its end at 16: 20 dB down at 17 (fewer satellites), clean at 18.
  EXPECT_LT(e.at(17).satellites, e.at(14).satellites);
  EXPECT_EQ(e.at(18).quality, 1);
  EXPECT_EQ(e.at(18).satellites, e.at(14).satellites);
  EXPECT_TRUE(test::contains(r.err, "fault jam ends at epoch 2024-05-01T00:00:16.000Z (+16.000 s) after 1 epochs, fading out over 2 s"))
      << r.err;
}

}  // namespace faults_triggers_test
}  // namespace
}  // namespace gpsemu
