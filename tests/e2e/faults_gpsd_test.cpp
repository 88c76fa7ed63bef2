// The second stage of the fault catalogue through the binary, on a pty with the real gpsd reading
// it (Debian's gpsd; missing is a failure, not a skip): sky-mask (SKY lists fewer satellites, eph
// up, a tunnel entry loses the fix), spoof (gpsd's position and speed follow the drag), time (a
// jump and a week-number rollover in TPV's time) and reset (silent, a cold start, gpsd back to a
// 3-D fix), each at its epochs. The emulator runs at 5 Hz from a fixed start time, paced in real
// time (gpsd reads a live device), for a few seconds.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/model/geo.hpp"
#include "tests/support/gpsd.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_gpsd_test {

namespace fs = std::filesystem;
using namespace std::chrono;
using nlohmann::json;

constexpr const char* kStartTime = "2024-05-01T12:00:00Z";
constexpr std::int64_t kStartMsOfDay = 12 * 3600 * 1000;
const Geodetic kOrigin{43.0725, -89.4125, 260.0};  // gpsemu's default origin (sim:stationary)

struct Report {
  std::optional<std::int64_t> since_ms;  ///< TPV: its time after the first epoch; SKY: the last TPV's
  std::string time;                      ///< TPV: gpsd's ISO 8601 time
  int mode = 0;
  double eph_m = NAN, lat_deg = NAN, lon_deg = NAN, speed_mps = NAN;
  int sky_listed = -1, sky_used = -1;  ///< SKY: satellites listed, used
  int status = 1;  ///< TPV: gpsd's fix status (2 DGPS, 3 RTK fixed, 4 RTK float; absent: 1)
};

/// gpsemu at 5 Hz on a pty from kStartTime with `scenario`, gpsd attached, for `duration_s`:
/// gpsd's TPV and SKY reports in order.
std::vector<Report> run_with_gpsd(const std::string& name, const std::string& scenario, double duration_s,
                                  std::vector<std::string> args = {}) {
  std::vector<Report> out;
  const fs::path dir = test::scratch_dir("faults_gpsd", name);
  const fs::path link = dir / "gps";
  const fs::path file = test::write_file(dir / "scenario.toml", scenario);
  std::vector<std::string> argv{GPSEMU_BINARY, "--output", "pty:" + link.string(), "--rate", "5", "--start-time",
                                kStartTime, "--clock", "scaled:1", "--duration", fmt::format("{}", duration_s),
                                "--seed", "21", "--scenario", file.string(), "--log-level", "info"};
  argv.insert(argv.end(), args.begin(), args.end());
  test::Process gpsemu(argv);
  test::GpsdWatch gpsd(gpsemu, link, test::GpsdAccess::read_only);
  if (!gpsd.ok()) {
    ADD_FAILURE() << gpsd.error();
    return out;
  }
  std::optional<std::int64_t> last_tpv_ms;
  gpsd.read_reports(milliseconds(std::llround(duration_s * 1000.0) + 1500), [&](const json& j) {
    Report r;
    if (j["class"] == "TPV") {
      const test::Tpv tpv = test::tpv_of(j);
      r.mode = tpv.mode;
      r.eph_m = tpv.eph_m;
      r.lat_deg = tpv.lat_deg;
      r.lon_deg = tpv.lon_deg;
      r.speed_mps = j.value("speed", NAN);
      r.status = j.value("status", 1);
      r.time = j.value("time", "");
      if (tpv.time_of_day_ms) r.since_ms = last_tpv_ms = *tpv.time_of_day_ms - kStartMsOfDay;
    } else if (j["class"] == "SKY" && j.contains("satellites")) {
      r.since_ms = last_tpv_ms;
      r.sky_listed = static_cast<int>(j["satellites"].size());
      r.sky_used = 0;
      for (const json& s : j["satellites"]) r.sky_used += s.value("used", false);
    } else {
      return;
    }
    out.push_back(r);
  });
  gpsd.close_client();
  EXPECT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  gpsd.stop();
  fs::remove_all(dir);
  return out;
}

/// The TPVs whose time falls in [from_ms, to_ms) after the first epoch.
std::vector<Report> tpvs_in(const std::vector<Report>& reports, std::int64_t from_ms, std::int64_t to_ms) {
  std::vector<Report> out;
  for (const Report& r : reports) {
    if (r.sky_listed < 0 && r.since_ms && *r.since_ms >= from_ms && *r.since_ms < to_ms) out.push_back(r);
  }
  return out;
}

/// The SKYs after a TPV of [from_ms, to_ms).
std::vector<Report> skies_in(const std::vector<Report>& reports, std::int64_t from_ms, std::int64_t to_ms) {
  std::vector<Report> out;
  for (const Report& r : reports) {
    if (r.sky_listed >= 0 && r.since_ms && *r.since_ms >= from_ms && *r.since_ms < to_ms) out.push_back(r);
  }
  return out;
}

double east_m_of(const Report& r) { return (r.lon_deg - kOrigin.lon_deg) * 111320.0 * std::cos(kOrigin.lat_deg * M_PI / 180.0); }
double north_m_of(const Report& r) { return (r.lat_deg - kOrigin.lat_deg) * 111320.0; }

TEST(FaultsGpsd, SkyMaskListsFewerSatellitesRaisesEphAndATunnelEntryLosesTheFix) {
  const auto reports = run_with_gpsd("skymask",
                                     "[[fault]]\nkind = \"sky-mask\"\nat = 2\nduration = 2\nmask = \"0-150:90\"\n"
                                     "[[fault]]\nkind = \"sky-mask\"\nat = 5\nduration = 1.4\nmask = \"tunnel-entry\"\n",
                                     8.0);
  const auto before = tpvs_in(reports, 1000, 2000), masked = tpvs_in(reports, 2200, 4000);
  const auto tunnel = tpvs_in(reports, 5000, 6400), after = tpvs_in(reports, 6600, 8000);
  ASSERT_FALSE(before.empty());
  ASSERT_FALSE(masked.empty());
  ASSERT_FALSE(tunnel.empty());
  ASSERT_FALSE(after.empty());
  // gpsd's first report after it attaches or a fix returns may come before it has the whole cycle
  // (2-D to it): a fix is mode 2 or 3, the last of a window 3.
  for (const auto& r : before) EXPECT_GE(r.mode, 2);
  EXPECT_EQ(before.back().mode, 3);
  for (const auto& r : masked) EXPECT_EQ(r.mode, 3) << "still 3-D behind the mask at " << *r.since_ms;
  for (const auto& r : tunnel) EXPECT_LE(r.mode, 1) << "no fix at the tunnel entry at " << *r.since_ms;
  for (const auto& r : after) EXPECT_GE(r.mode, 2);
  EXPECT_EQ(after.back().mode, 3);
  EXPECT_GT(masked.back().eph_m, before.back().eph_m * 1.05) << "eph from the poorer geometry";
  const auto sky_before = skies_in(reports, 1000, 1800), sky_masked = skies_in(reports, 2400, 3800);
  ASSERT_FALSE(sky_before.empty());
  ASSERT_FALSE(sky_masked.empty());
  EXPECT_LT(sky_masked.back().sky_listed, sky_before.back().sky_listed) << "the masked satellites are not in view";
  EXPECT_LT(sky_masked.back().sky_used, sky_before.back().sky_used);
  std::cout << fmt::format("sky-mask: SKY {} listed / {} used before, {} / {} behind the mask; eph {:.2f} m then {:.2f} m\n",
                           sky_before.back().sky_listed, sky_before.back().sky_used, sky_masked.back().sky_listed,
                           sky_masked.back().sky_used, before.back().eph_m, masked.back().eph_m);
}

TEST(FaultsGpsd, SpoofDragsGpsdsPositionAndSpeedAway) {
  const auto reports = run_with_gpsd(
      "spoof", "[[fault]]\nkind = \"spoof\"\nat = 2\nduration = 4\nspeed_mps = 20\nbearing_deg = 90\n", 7.0);
  const auto before = tpvs_in(reports, 1000, 2000), spoofed = tpvs_in(reports, 2200, 6000);
  ASSERT_FALSE(before.empty());
  ASSERT_GE(spoofed.size(), 10u);
  for (const auto& r : spoofed) EXPECT_EQ(r.mode, 3) << "a spoof keeps a good fix";
  // Dragged east at 20 m/s (the truth stands still; the noise moves centimetres).
  const Report& a = spoofed.front();
  const Report& b = spoofed.back();
  const double rate_mps = (east_m_of(b) - east_m_of(a)) / ((*b.since_ms - *a.since_ms) / 1000.0);
  EXPECT_NEAR(rate_mps, 20.0, 1.0);
  EXPECT_NEAR(east_m_of(a) - east_m_of(before.back()), 20.0 * (*a.since_ms - 2000) / 1000.0, 3.0);
  EXPECT_NEAR(b.speed_mps, 20.0, 0.5) << "the velocity agrees with the drag";
  const auto after = tpvs_in(reports, 6000, 7000);
  ASSERT_FALSE(after.empty());
  EXPECT_NEAR(east_m_of(after.back()), east_m_of(before.back()), 3.0) << "back on the truth";
}

// The position faults of the first stage: a jump (40 m east) and a wrong offset (60 m south) move
// gpsd's position by their offsets at their epochs only; a fix-quality of rtk-fixed is gpsd's
// status 3 (RTK fixed); a freeze repeats the last fix's position with new times (over a decaying
// jump that would move it metres an epoch).
TEST(FaultsGpsd, JumpWrongFixQualityAndFreezeShowInGpsdsFixAtTheirEpochs) {
  const auto reports = run_with_gpsd("position",
                                     "[[fault]]\nkind = \"jump\"\nat = 1.6\nduration = 1.4\neast_m = 40\n"
                                     "[[fault]]\nkind = \"wrong\"\nat = 3.6\nduration = 1.4\nnorth_m = -60\n"
                                     "[[fault]]\nkind = \"fix-quality\"\nat = 5.6\nduration = 1.4\nquality = \"rtk-fixed\"\n"
                                     // The freeze after a decaying jump: it holds the fix from before both.
                                     "[[fault]]\nkind = \"jump\"\nat = 7.6\nduration = 1.4\neast_m = 40\ndecay_s = 1\n"
                                     "[[fault]]\nkind = \"freeze\"\nat = 7.6\nduration = 1.4\n",
                                     9.4);
  const auto before = tpvs_in(reports, 600, 1600), jumped = tpvs_in(reports, 1600, 3000);
  const auto wrong = tpvs_in(reports, 3600, 5000), rtk = tpvs_in(reports, 5600, 7000);
  const auto frozen = tpvs_in(reports, 7600, 9000), clean = tpvs_in(reports, 3000, 3600);
  ASSERT_FALSE(before.empty());
  ASSERT_GE(jumped.size(), 5u);
  ASSERT_GE(wrong.size(), 5u);
  ASSERT_GE(rtk.size(), 5u);
  ASSERT_GE(frozen.size(), 5u);
  ASSERT_FALSE(clean.empty());
  const Report& ref = before.back();
  for (const auto& r : jumped) {
    EXPECT_EQ(r.mode, 3);
    EXPECT_NEAR(east_m_of(r) - east_m_of(ref), 40.0, 5.0) << "jump at " << *r.since_ms;
    EXPECT_NEAR(north_m_of(r) - north_m_of(ref), 0.0, 5.0);
  }
  for (const auto& r : clean) EXPECT_NEAR(east_m_of(r) - east_m_of(ref), 0.0, 5.0) << "back at " << *r.since_ms;
  for (const auto& r : wrong) {
    EXPECT_EQ(r.mode, 3);
    EXPECT_NEAR(north_m_of(r) - north_m_of(ref), -60.0, 5.0) << "wrong at " << *r.since_ms;
    EXPECT_NEAR(east_m_of(r) - east_m_of(ref), 0.0, 5.0);
  }
  for (const auto& r : before) EXPECT_EQ(r.status, 1);
  for (const auto& r : rtk) {
    EXPECT_EQ(r.mode, 3);
    EXPECT_EQ(r.status, 3) << "RTK fixed at " << *r.since_ms;
  }
  const auto last_clean = tpvs_in(reports, 7400, 7600);
  ASSERT_FALSE(last_clean.empty());
  for (const auto& r : frozen) {
    EXPECT_EQ(r.mode, 3);
    EXPECT_EQ(r.lat_deg, last_clean.back().lat_deg) << "frozen at " << *r.since_ms;
    EXPECT_EQ(r.lon_deg, last_clean.back().lon_deg) << "frozen at " << *r.since_ms;
  }
  EXPECT_NE(frozen.front().time, frozen.back().time) << "new times";
}

constexpr const char* kTimeScenario =
    "[[fault]]\nkind = \"time\"\nmode = \"jump\"\njump_s = 3600\nat = 2\nduration = 1.4\n"
    "[[fault]]\nkind = \"time\"\nmode = \"rollover\"\nat = 4.6\nduration = 1.4\n";

// The jump shows in gpsd's time; the rollover's date 1024 weeks early is what gpsemu writes (RMC
// 150904 in place of 010524), and gpsd 3.22 undoes it (its own week-rollover defence: a date
// before its build is taken 1024 weeks later), so its TPVs keep the right date with a 3-D fix.
TEST(FaultsGpsd, TimeJumpAndWeekRolloverShowInGpsdsTime) {
  const auto reports = run_with_gpsd("time", kTimeScenario, 7.0);
  int jumped = 0, rolled = 0, normal = 0;
  for (const Report& r : reports) {
    if (r.sky_listed >= 0 || r.time.empty()) continue;
    EXPECT_GE(r.mode, 2) << "a fix at " << r.time;  // gpsd may see a jumped cycle as 2-D
    if (r.time.rfind("2024-05-01T13:00:0", 0) == 0) {
      ++jumped;  // 12:00:02..12:00:03.2 an hour later
      continue;
    }
    EXPECT_EQ(r.time.rfind("2024-05-01T12:00:0", 0), 0u) << r.time;
    const std::int64_t ms = *r.since_ms;
    EXPECT_FALSE(ms >= 2000 && ms < 3400) << "an unshifted time inside the jump: " << r.time;
    ++(ms >= 4600 && ms < 6000 ? rolled : normal);
  }
  std::cout << fmt::format("time: {} TPVs an hour late, {} in the rollover, {} on time\n", jumped, rolled, normal);
  EXPECT_GE(jumped, 5);
  EXPECT_GE(rolled, 5);
  EXPECT_GE(normal, 10);
  // What gpsemu wrote for the same scenario: the RMC date of each epoch.
  const fs::path dir = test::scratch_dir("faults_gpsd", "time_fast");
  const fs::path file = test::write_file(dir / "time.toml", kTimeScenario);
  const test::Result fast = test::run({GPSEMU_BINARY, "--fast", "--output", "stdout", "--rate", "5", "--start-time", kStartTime, "--duration",
                                       "7", "--seed", "21", "--scenario", file.string()});
  ASSERT_EQ(fast.status, 0) << fast.err;
  int rmc = 0;
  std::istringstream lines(fast.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("RMC,") != 3) continue;
    // $GPRMC,hhmmss.ss,A,lat,N,lon,W,speed,course,ddmmyy: the 10th field.
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    ASSERT_GE(f.size(), 10u) << line;
    const int hh = std::stoi(f[1].substr(0, 2)), mm = std::stoi(f[1].substr(2, 2));
    const double ss = std::stod(f[1].substr(4));
    const double since_s = (hh - 12) * 3600 + mm * 60 + ss;
    const bool rollover = since_s >= 4.6 && since_s < 6.0;
    EXPECT_EQ(f[9], rollover ? "150904" : "010524") << line;
    EXPECT_FALSE(since_s >= 2.0 && since_s < 3.4) << "the jump's epochs are an hour late: " << line;
    ++rmc;
  }
  EXPECT_EQ(rmc, 35);
  fs::remove_all(dir);
}

TEST(FaultsGpsd, ResetIsSilentThenAColdStartAndGpsdRecovers) {
  const auto reports =
      run_with_gpsd("reset", "[[fault]]\nkind = \"reset\"\nat = 2\nsilent_s = 1\nttff_s = 2\n", 7.0);
  EXPECT_TRUE(tpvs_in(reports, 2000, 3000).empty()) << "nothing written while it boots";
  for (const auto& r : tpvs_in(reports, 1000, 2000)) EXPECT_GE(r.mode, 2);
  for (const auto& r : tpvs_in(reports, 3000, 5000)) EXPECT_LE(r.mode, 1) << "cold at " << *r.since_ms;
  const auto after = tpvs_in(reports, 5200, 7000);
  ASSERT_FALSE(after.empty()) << "gpsd did not recover";
  for (const auto& r : after) EXPECT_GE(r.mode, 2) << "back at " << *r.since_ms;  // the first may be 2-D to gpsd
  EXPECT_EQ(after.back().mode, 3);
}

}  // namespace faults_gpsd_test
}  // namespace
}  // namespace gpsemu
