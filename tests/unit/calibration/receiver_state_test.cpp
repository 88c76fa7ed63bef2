// The receiver's state learned from a log (calibration/receiver_state.hpp): satellites, DOPs,
// C/N0 and the lowest elevation used from GGA/GSA/GSV, the UERE; and the gate test of issue #24:
// the calibrated config of every real log in tests/data/real (gpsd's regression logs, BSD-2-Clause,
// tests/data/real/LICENSE) passes PX4's default EKF2 GPS checks (EKF2_REQ_NSATS 6, EKF2_REQ_PDOP
// 2.5, EKF2_REQ_EPH 3 m) and ArduPilot's HDOP arming check (2.5) wherever the real log does.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <unistd.h>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/calibration/receiver_state.hpp"
#include "emulator/config/config.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/model/receiver.hpp"
#include "tests/support/nmea_check.hpp"
#include "tests/support/paths.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::calibration {
namespace {
namespace receiver_state_test {

TEST(ReceiverStateLearning, SatellitesDopsCn0AndTheLowestElevationUsed) {
  const std::string log =
      "$GPGSV,2,1,05,01,40,083,46,02,17,308,41,12,07,344,39,14,22,228,45*78\r\n"
      "$GPGSV,2,2,05,65,55,120,44*4C\r\n"
      "$GNGSA,A,3,01,02,14,,,,,,,,,,1.80,1.10,1.40,1*0B\r\n"
      "$GNGSA,A,3,65,,,,,,,,,,,,1.80,1.10,1.40,2*0D\r\n"
      "$GNGGA,120000.00,4304.35012,N,08924.75027,W,1,04,1.10,260.1,M,-34.7,M,,*79\r\n"
      "$GNGGA,120001.00,4304.35012,N,08924.75027,W,1,06,0.90,260.1,M,-34.7,M,,*73\r\n"
      "$GNGGA,120002.00,,,,,0,00,99.99,,,,,,*79\r\n";
  const ReceiverState s = with_sigmas(learn_receiver_state(log), 1.5, 0.0);
  ASSERT_TRUE(s.satellites_used && s.hdop && s.pdop && s.cn0_dbhz);
  EXPECT_EQ(s.satellites_used->count, 2u) << "no-fix epochs are not counted";
  EXPECT_EQ(s.hdop->median, 1.10);
  EXPECT_EQ(s.pdop->median, 1.80);
  EXPECT_EQ(s.cn0_dbhz->count, 5u);
  EXPECT_EQ(s.cn0_dbhz->median, 44.0);
  ASSERT_TRUE(s.lowest_used_elevation_deg);
  EXPECT_EQ(*s.lowest_used_elevation_deg, 17.0) << "PRN 12 at 7 degrees is tracked, not used";
  ASSERT_TRUE(s.uere_m);
  EXPECT_NEAR(*s.uere_m, 1.5 / 1.10, 1e-12);
  const std::string toml = receiver_state_toml(s);
  EXPECT_NE(toml.find("elevation-mask = 17\n"), std::string::npos) << toml;
  EXPECT_NE(toml.find("uere = 1.364\n"), std::string::npos) << toml;
  EXPECT_NE(toml.find("satellites = 6\n"), std::string::npos) << toml;
  EXPECT_NE(receiver_state_summary(s).find("HDOP 1.10"), std::string::npos);
}

// Issue 34: a DGPS or RTK log's profile reported GGA quality 1 (its noise, already the receiver's
// at its quality, would have been scaled again by --fix-quality); issue 36: the reported accuracy
// ignored what the receiver itself claims. The log's quality and its GST's ratio are learned.
TEST(ReceiverStateLearning, TheLogsFixQualityAndItsGstOverTheScatterAreLearned) {
  std::string log;
  for (int k = 0; k < 5; ++k) {
    log += test::sentence(fmt::format("GPGGA,12000{}.00,4304.35012,N,08924.75027,W,{},09,0.90,260.1,M,-34.7,M,1.0,0000",
                                      k, k == 4 ? 1 : 2));
    log += test::sentence(fmt::format("GPGST,12000{}.00,1.2,0.5,0.4,10.0,{:.2f},0.40,0.90", k, 0.30 + 0.01 * k));
  }
  const ReceiverState s = with_sigmas(learn_receiver_state(log), 0.8, 1.0);  // the model's long-run sigma_h 1 m
  ASSERT_TRUE(s.fix_quality && s.gst_sigma_h_m && s.accuracy_ratio);
  EXPECT_EQ(*s.fix_quality, 2) << "four DGPS epochs, one autonomous";
  EXPECT_EQ(s.gst_sigma_h_m->count, 5u);
  EXPECT_NEAR(s.gst_sigma_h_m->median, std::hypot(0.32, 0.40), 1e-12);
  EXPECT_NEAR(*s.accuracy_ratio, std::hypot(0.32, 0.40), 1e-12);
  const std::string toml = receiver_state_toml(s);
  EXPECT_NE(toml.find("fix-quality = \"dgps\"\nnoise-quality = \"dgps\"\n"), std::string::npos) << toml;
  EXPECT_NE(toml.find("accuracy-ratio = 0.512\n"), std::string::npos) << toml;
  EXPECT_NE(receiver_state_summary(s).find("fix quality 2 (dgps)"), std::string::npos) << receiver_state_summary(s);
  // A log without GST at quality 1: no fix quality, and the receiver claims the scatter of its log
  // (0.8 m) where the model's error over a long run is 2 m.
  const ReceiverState p = with_sigmas(learn_receiver_state(std::string(
      "$GNGGA,120001.00,4304.35012,N,08924.75027,W,1,06,0.90,260.1,M,-34.7,M,,*73\r\n")), 0.8, 2.0);
  const std::string plain = receiver_state_toml(p);
  EXPECT_EQ(plain.find("fix-quality"), std::string::npos) << plain;
  EXPECT_NE(plain.find("accuracy-ratio = 0.400\n"), std::string::npos) << plain;
  EXPECT_NE(plain.find("no GST"), std::string::npos) << plain;
}

// Issue 22 point 9: calibrate learned the state from the whole log read into memory (14x the file
// at its end); it now reads the log as a stream, 1 MiB at a time, and learns the same.
TEST(ReceiverStateLearning, AStreamedLogTeachesWhatTheWholeTextDoes) {
  const std::filesystem::path path = std::filesystem::path(GPSEMU_SOURCE_DIR) / "tests/data/real/ublox-zed-f9p_hpg1.11.log";
  std::ifstream whole_in(path, std::ios::binary);
  const std::string once{std::istreambuf_iterator<char>(whole_in), std::istreambuf_iterator<char>()};
  ASSERT_FALSE(once.empty()) << path;
  std::string whole;
  for (int k = 0; k < 6; ++k) whole += once;  // 1.5 MB: read in two chunks, a sentence cut between them
  const ReceiverState a = learn_receiver_state(std::string_view(whole));
  std::istringstream in(whole);
  const ReceiverState b = learn_receiver_state(in);
  ASSERT_TRUE(a.satellites_used && b.satellites_used && a.hdop && b.hdop);
  EXPECT_EQ(a.satellites_used->count, b.satellites_used->count);
  EXPECT_EQ(a.satellites_used->median, b.satellites_used->median);
  EXPECT_EQ(a.hdop->median, b.hdop->median);
  ASSERT_EQ(a.cn0_dbhz.has_value(), b.cn0_dbhz.has_value());
  if (a.cn0_dbhz) {
    EXPECT_EQ(a.cn0_dbhz->count, b.cn0_dbhz->count);
  }
  EXPECT_EQ(a.lowest_used_elevation_deg, b.lowest_used_elevation_deg);
}

const std::string kDir = std::string(GPSEMU_SOURCE_DIR) + "/tests/data/real";

class CalibratedGates : public ::testing::TestWithParam<const char*> {};

TEST_P(CalibratedGates, PassAutopilotGpsChecksWhereverTheRealLogDoes) {
  const std::string path = kDir + "/" + GetParam();
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  CalibrateOptions options;
  options.runs = 2;
  const Calibration c = calibrate(read_receiver_log_file(path), options);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const double sigma_h_m = std::hypot(c.real[0].sd_m, c.real[1].sd_m);
  const Enu model_sigma_m = estimate_noise_sigma_m(c.models[c.best].config, 1);  // as calibrate does
  const ReceiverState state =
      with_sigmas(learn_receiver_state(bytes), sigma_h_m, std::hypot(model_sigma_m.east_m, model_sigma_m.north_m));
  ASSERT_TRUE(state.satellites_used && state.hdop);
  GateCheck real;
  real.satellites = static_cast<int>(std::lround(state.satellites_used->median));
  real.hdop = state.hdop->median;
  real.pdop = state.pdop ? state.pdop->median : 1.5 * state.hdop->median;
  real.eph_m = sigma_h_m;

  const auto toml_path = test::scratch_root() / fmt::format("gpsemu_gates_{}_{}.toml", ::getpid(), GetParam());
  std::ofstream(toml_path) << config_toml(c, path) << receiver_state_toml(state);
  const Config config = build_config(toml_path.string(), {});
  std::filesystem::remove(toml_path);
  const ReceiverSettings& r = config.receiver();
  const LocalFrame frame(r.origin);
  const UtcNs start = parse_iso8601_utc("2024-05-01T12:00:00Z");
  Receiver rx(frame, receiver_options(r), noise::make_noise_model(r.noise, r.seed), start);
  int px4 = 0, ardupilot = 0, n = 0;
  GateCheck worst{99, 0, 0, 0};
  for (int k = 0; k < 900; ++k, ++n) {
    const nmea::Fix fix = rx.fix_at(start + std::chrono::seconds{k}, sources::Truth{});
    ASSERT_TRUE(fix.has_fix()) << k;
    const GateCheck g{fix.satellites_used, fix.hdop, fix.pdop, std::hypot(fix.sigma_lat_m, fix.sigma_lon_m)};
    px4 += g.px4_ok();
    ardupilot += g.ardupilot_ok();
    worst = {std::min(worst.satellites, g.satellites), std::max(worst.hdop, g.hdop), std::max(worst.pdop, g.pdop),
             std::max(worst.eph_m, g.eph_m)};
  }
  std::cout << fmt::format("{}: real {} satellites, HDOP {:.2f}, PDOP {:.2f}, eph {:.2f} m (PX4 {}, ArduPilot {}); "
                           "calibrated over {} s: worst {} satellites, HDOP {:.2f}, PDOP {:.2f}, eph {:.2f} m; "
                           "PX4 gates passed {}/{}, ArduPilot {}/{}\n",
                           GetParam(), real.satellites, real.hdop, real.pdop, real.eph_m, real.px4_ok() ? "ok" : "refuses",
                           real.ardupilot_ok() ? "ok" : "refuses", n, worst.satellites, worst.hdop, worst.pdop,
                           worst.eph_m, px4, n, ardupilot, n);
  if (real.px4_ok()) {
    EXPECT_EQ(px4, n) << "PX4's EKF2 would refuse the emulated receiver";
  }
  if (real.ardupilot_ok()) {
    EXPECT_EQ(ardupilot, n) << "ArduPilot's HDOP check would fail";
  }
  // The emulated state resembles the log's: its HDOP within a factor 2 of the real median.
  EXPECT_LT(worst.hdop, 2.0 * real.hdop + 0.3);
}

INSTANTIATE_TEST_SUITE_P(RealLogs, CalibratedGates,
                         ::testing::Values("ublox-zed-f9p_hpg1.11.log", "telit-he910.log", "quectel-l76k-dual.log"),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& ch : n) {
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           }
                           return n;
                         });

}  // namespace receiver_state_test
}  // namespace
}  // namespace gpsemu::calibration
