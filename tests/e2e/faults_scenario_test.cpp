// A scenario of faults through the binary (--fast, a fixed start): each fault shows in GGA (quality,
// satellites, HDOP), RMC (status) and a u-blox's NAV-PVT (fixType) at exactly its epochs; the
// same scenario and seed give the same bytes; [[fault]] tables work inside --config too; a bad
// key is one clear message and exit 2.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_scenario_test {

// Epoch k is at second k of the day (run_fast starts at 2024-05-01T00:00:00Z, 1 Hz).
constexpr const char* kScenario = R"(
[[fault]]
kind = "outage"
at = 2
duration = 2
[[fault]]
kind = "fix-quality"
at = 5
duration = 2
quality = "rtk-fixed"
[[fault]]
kind = "degrade"
at = 8
duration = 2
satellites = 5
[[fault]]
kind = "jam"
at = 11
duration = 2
db = 40
[[fault]]
kind = "silence"
at = 14
duration = 2
[[fault]]
kind = "freeze"
at = 17
duration = 2
[[fault]]
kind = "jump"
at = 20
duration = 2
east_m = 100
)";

struct Epoch {
  int quality = -1, satellites = -1;
  double hdop = NAN, lat_deg = NAN, lon_deg = NAN;
  bool rmc_active = false, has_rmc = false;
};

std::map<int, Epoch> epochs_in(const std::string& text) {
  std::map<int, Epoch> out;
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(text)) {
    if (s.type == "GGA") {
      const auto gga = nmea::parse_gga(s);
      if (!gga.ok() || !gga->time_of_day) continue;
      Epoch& e = out[static_cast<int>(gga->time_of_day->count() / 1000)];
      e.quality = static_cast<int>(gga->quality);
      e.satellites = gga->satellites.value_or(-1);
      e.hdop = gga->hdop.value_or(NAN);
      e.lat_deg = gga->lat_deg.value_or(NAN);
      e.lon_deg = gga->lon_deg.value_or(NAN);
    } else if (s.type == "RMC") {
      const auto rmc = nmea::parse_rmc(s);
      if (!rmc.ok() || !rmc->time_of_day) continue;
      Epoch& e = out[static_cast<int>(rmc->time_of_day->count() / 1000)];
      e.has_rmc = true;
      e.rmc_active = rmc->status_active;
    }
  }
  return out;
}

TEST(FaultsScenario, EachFaultShowsInGgaAndRmcAtItsEpochs) {
  const auto dir = test::scratch_dir("faults", "nmea");
  const auto scenario = test::write_file(dir / "scenario.toml", kScenario);
  const test::Result r = test::run_fast(GPSEMU_BINARY, {"--duration", "24", "--seed", "5", "--scenario", scenario.string(),
                                                        "--log-level", "info"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::map<int, Epoch> e = epochs_in(r.out);
  ASSERT_EQ(e.size(), 22u) << "24 epochs, 2 of them silent";
  const Epoch& normal = e.at(0);
  ASSERT_EQ(normal.quality, 1);
  ASSERT_TRUE(normal.rmc_active);
  for (const int k : {2, 3, 11, 12}) {  // outage, jam: no fix
    EXPECT_EQ(e.at(k).quality, 0) << k;
    EXPECT_FALSE(e.at(k).rmc_active) << k;
    EXPECT_TRUE(std::isnan(e.at(k).lat_deg)) << k;
  }
  EXPECT_EQ(e.at(2).satellites, 0);  // an outage has none in view
  for (const int k : {5, 6}) EXPECT_EQ(e.at(k).quality, 4) << k;  // rtk-fixed
  for (const int k : {8, 9}) {  // degrade: 5 satellites, a larger HDOP
    EXPECT_EQ(e.at(k).satellites, 5) << k;
    EXPECT_GT(e.at(k).hdop, normal.hdop) << k;
    EXPECT_TRUE(e.at(k).rmc_active) << k;
  }
  EXPECT_FALSE(e.count(14) || e.count(15)) << "silence writes nothing";
  for (const int k : {17, 18}) {  // freeze: epoch 16's position again
    EXPECT_EQ(e.at(k).lat_deg, e.at(16).lat_deg) << k;
    EXPECT_EQ(e.at(k).lon_deg, e.at(16).lon_deg) << k;
  }
  // jump: 100 m east (the noise moves a metre at most between epochs).
  const double east_m = (e.at(20).lon_deg - e.at(19).lon_deg) * 111320.0 * std::cos(43.0725 * M_PI / 180.0);
  EXPECT_NEAR(east_m, 100.0, 2.0);
  EXPECT_EQ(e.at(22).quality, 1);
  EXPECT_EQ(e.at(22).satellites, normal.satellites);
  // Each start and end logged with its epoch time; the summary counts each fault's epochs.
  EXPECT_TRUE(test::contains(r.err, "fault jam db=40 at 11 s for 2 s starts at epoch 2024-05-01T00:00:11.000Z")) << r.err;
  EXPECT_TRUE(test::contains(r.err, "fault jam ends at epoch 2024-05-01T00:00:13.000Z")) << r.err;
  EXPECT_TRUE(test::contains(r.err, "fault outage at 2 s for 2 s: 2 epochs")) << r.err;
  EXPECT_TRUE(test::contains(r.err, "2 epochs silent")) << r.err;
}

TEST(FaultsScenario, SameScenarioAndSeedGiveTheSameBytes) {
  const auto dir = test::scratch_dir("faults", "same");
  const auto scenario = test::write_file(dir / "scenario.toml", kScenario);
  const std::vector<std::string> args{"--duration", "24", "--seed", "6", "--scenario", scenario.string(),
                                      "--protocol", "nmea+ubx", "--source", "sim:circle"};
  const test::Result a = test::run_fast(GPSEMU_BINARY, args);
  const test::Result b = test::run_fast(GPSEMU_BINARY, args);
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_FALSE(a.out.empty());
  EXPECT_TRUE(a.out == b.out);
}

TEST(FaultsScenario, NavPvtFixTypeFollowsTheFaultsOfAUbloxReceiver) {
  const auto dir = test::scratch_dir("faults", "ubx");
  const auto config = test::write_file(dir / "run.toml", std::string("protocol = \"ubx\"\n") + kScenario);
  const test::Result r = test::run_fast(GPSEMU_BINARY, {"--duration", "24", "--seed", "5", "--config", config.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  std::map<int, int> fix_type;  // by second since the first solution
  std::optional<std::uint32_t> first_itow;
  ubx::FrameReader reader;
  for (const ubx::ClientMessage& m : reader.feed(r.out)) {
    const auto* f = std::get_if<ubx::Frame>(&m);
    if (f == nullptr || f->id != ubx::msg::nav_pvt) continue;
    const std::uint32_t itow = ubx::get_u4(f->payload, 0);
    if (!first_itow) first_itow = itow;
    fix_type[static_cast<int>((itow - *first_itow) / 1000)] = ubx::get_u1(f->payload, 20);
  }
  ASSERT_EQ(fix_type.size(), 22u);
  EXPECT_EQ(fix_type.at(0), 3);
  for (const int k : {2, 3, 11, 12}) EXPECT_EQ(fix_type.at(k), 0) << k;
  for (const int k : {5, 8, 17, 20}) EXPECT_EQ(fix_type.at(k), 3) << k;
  EXPECT_FALSE(fix_type.count(14) || fix_type.count(15));
}

TEST(FaultsScenario, AFaultForOneReceiverOfAFleetLeavesTheOthers) {
  const auto dir = test::scratch_dir("faults", "fleet");
  const auto scenario = test::write_file(dir / "fleet.toml", "[[fault]]\nkind = \"outage\"\nat = 1\nduration = 2\nreceiver = 1\n");
  const test::Result r = test::run({GPSEMU_BINARY, "--fast", "--start-time", "2024-05-01T00:00:00Z", "--duration", "5",
                                    "--receivers", "2", "--output", "file:" + (dir / "r{i}.nmea").string(), "--scenario",
                                    scenario.string(), "--log-level", "info"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::map<int, Epoch> r0 = epochs_in(test::read_file(dir / "r0.nmea"));
  const std::map<int, Epoch> r1 = epochs_in(test::read_file(dir / "r1.nmea"));
  ASSERT_EQ(r0.size(), 5u);
  ASSERT_EQ(r1.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(r0.at(k).quality, 1) << k;
    EXPECT_EQ(r1.at(k).quality, k == 1 || k == 2 ? 0 : 1) << k;
  }
  EXPECT_TRUE(test::contains(r.err, "receiver 1: fault outage at 1 s for 2 s, receiver 1 starts at epoch")) << r.err;
}

TEST(FaultsScenario, ABadKeyIsOneClearMessageAndExit2) {
  const auto dir = test::scratch_dir("faults", "bad");
  const auto scenario = test::write_file(dir / "bad.toml", "[[fault]]\nkind = \"jam\"\nat = 3\ndb = 25\nramp = 5\n");
  const test::Result r = test::run_fast(GPSEMU_BINARY, {"--duration", "5", "--scenario", scenario.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(test::contains(r.err, "ramp: not a parameter of jam (its parameters: db, leave, ramp_out_s, ramp_s")) << r.err;
  EXPECT_TRUE(test::contains(r.err, "bad.toml:5")) << r.err;  // the line of the key at fault
  const auto other = test::write_file(dir / "other.toml", "[[fault]]\nkind = \"outage\"\nreceiver = 3\n");
  const test::Result n = test::run_fast(GPSEMU_BINARY, {"--duration", "5", "--scenario", other.string()});
  EXPECT_EQ(n.status, 2);
  EXPECT_TRUE(test::contains(n.err, "other.toml:3: [[fault]]: receiver: there is no receiver 3")) << n.err;
}

// Without --start-time the run begins now: an at_utc the run never reaches, or one over before it
// begins, is refused at start-up as an `at` past --duration is (it was accepted, 0 epochs).
TEST(FaultsScenario, AnAtUtcOutsideARunThatStartsNowIsRefused) {
  const auto dir = test::scratch_dir("faults", "utc-now");
  const auto late = test::write_file(dir / "late.toml", "[[fault]]\nkind = \"outage\"\n\nat_utc = \"2099-01-01T00:00:00Z\"\n");
  const test::Result r = test::run({GPSEMU_BINARY, "--fast", "--duration", "5", "--output", "stdout", "--scenario", late.string()});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(test::contains(r.err, "late.toml:4: [[fault]]: at_utc: 2099-01-01T00:00:00.000Z is not before the end of the run "
                                    "(its first epoch, now: "))
      << r.err;
  EXPECT_TRUE(test::contains(r.err, "--start-time T runs it at another time")) << r.err;
  EXPECT_EQ(r.out, "");  // refused before the first epoch
  const auto past = test::write_file(dir / "past.toml",
                                     "[[fault]]\nkind = \"jam\"\ndb = 30\nat_utc = \"2020-01-01T00:00:00Z\"\nduration = 60\n");
  const test::Result p = test::run({GPSEMU_BINARY, "--fast", "--duration", "5", "--output", "stdout", "--scenario", past.string()});
  EXPECT_EQ(p.status, 2) << p.err;
  EXPECT_TRUE(test::contains(p.err, "past.toml:4: [[fault]]: at_utc: 2020-01-01T00:00:00.000Z + 60 s is over before the run "
                                    "begins"))
      << p.err;
  // Begun before the run and still on: accepted, on from the first epoch.
  const auto on = test::write_file(dir / "on.toml", "[[fault]]\nkind = \"outage\"\nat_utc = \"2020-01-01T00:00:00Z\"\n");
  const test::Result ok = test::run({GPSEMU_BINARY, "--fast", "--duration", "3", "--output", "stdout", "--scenario", on.string()});
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_TRUE(test::contains(ok.err, "3 epochs emitted (3 without fix)")) << ok.err;
  std::filesystem::remove_all(dir);
}

// --duration 5 at 1 Hz: the last epoch is at 4 s, so a fault at 4.5 s would never start (it was
// accepted, "0 epochs" in the summary). A u-blox may be asked for a faster rate by its client: there
// the fault may still come, and it is accepted.
TEST(FaultsScenario, AFaultAfterTheLastEpochOfTheRunIsRefused) {
  const auto dir = test::scratch_dir("faults", "last-epoch");
  const auto late = test::write_file(dir / "late.toml", "[[fault]]\nkind = \"outage\"\nat = 4.5\n");
  const test::Result r = test::run_fast(GPSEMU_BINARY, {"--duration", "5", "--scenario", late.string()});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(test::contains(r.err, "late.toml:3: [[fault]]: at: 4.5 s is after the run's last epoch (at 4 s of --duration "
                                    "5 s): the fault would never start"))
      << r.err;
  EXPECT_EQ(r.out, "");
  const test::Result ten_hz = test::run_fast(GPSEMU_BINARY, {"--duration", "5", "--rate", "10", "--scenario", late.string()});
  EXPECT_EQ(ten_hz.status, 0) << ten_hz.err;
  const test::Result ublox =
      test::run_fast(GPSEMU_BINARY, {"--duration", "5", "--receiver", "ublox-m8n", "--scenario", late.string()});
  EXPECT_EQ(ublox.status, 0) << ublox.err;
  std::filesystem::remove_all(dir);
}

}  // namespace faults_scenario_test
}  // namespace
}  // namespace gpsemu
