// Reading a stationary receiver's log for calibration: what is skipped and counted, the detected
// rate and resolution, the ENU series about the mean position with its gaps.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "emulator/calibration/calibrate.hpp"
#include "emulator/calibration/receiver_log.hpp"
#include "emulator/calibration/series_stats.hpp"
#include "emulator/model/noise/cgrw_fit.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/calibration_logs.hpp"

namespace gpsemu::calibration {
namespace {
namespace log_test {

TEST(CalibrationLog, SkipsAndCountsJunk) {
  const test::MessyLog made = test::make_log(1.0, 300, 5, true);
  ReceiverLog log = read_receiver_log(made.text);
  EXPECT_EQ(log.fixes.size(), made.fixes);  // the repeated one is dropped
  EXPECT_EQ(log.counts.gga_no_fix, made.no_fix);
  EXPECT_EQ(log.counts.gga_malformed, made.malformed_gga);
  EXPECT_EQ(log.counts.repeated_time, made.repeated);
  EXPECT_EQ(log.counts.stream.bad_checksum, made.bad_checksum);
  EXPECT_EQ(log.counts.stream.comment_lines, 2u);
  EXPECT_GE(log.counts.stream.garbage_bytes + log.counts.stream.malformed, made.binary_frames);
  EXPECT_EQ(log.minute_decimals, 5);
  const EnuSeries s = to_enu_series(log);
  EXPECT_EQ(s.rate_hz, 1.0);
  EXPECT_EQ(s.size(), 300u);
  EXPECT_EQ(log.counts.missing_epochs, made.gaps + made.no_fix);
  std::size_t nan = 0;
  for (double v : s.axis_m[0]) nan += std::isnan(v);
  EXPECT_EQ(nan, made.gaps + made.no_fix);
  // Metres about the mean position: mean ~0, and the wander's size (0.8 + 0.3 m east).
  double mean = 0.0, n = 0.0, lo = 1e9, hi = -1e9;
  for (double v : s.axis_m[0])
    if (!std::isnan(v)) mean += v, n += 1, lo = std::min(lo, v), hi = std::max(hi, v);
  EXPECT_NEAR(mean / n, 0.0, 1e-6);
  EXPECT_NEAR(hi - lo, 2.1, 0.3);
}

TEST(CalibrationLog, DetectsRateAndResolution) {
  for (const double rate : {1.0, 5.0, 10.0}) {
    for (const int decimals : {4, 5, 7}) {
      ReceiverLog log = read_receiver_log(test::make_log(rate, 200, decimals, rate == 10.0).text);
      EXPECT_EQ(log.minute_decimals, decimals);
      EXPECT_EQ(to_enu_series(log).rate_hz, rate) << rate << " Hz, " << decimals << " decimals";
    }
  }
  EXPECT_EQ(snap_rate_hz(0.98), 1.0);
  EXPECT_EQ(snap_rate_hz(9.7), 10.0);
  EXPECT_EQ(snap_rate_hz(0.5), 0.5);
}

TEST(CalibrationLog, FourDecimalMinutesMakeMostFirstDifferencesZero) {
  ReceiverLog log = read_receiver_log(test::make_log(1.0, 300, 4, false).text);
  const EnuSeries s = to_enu_series(log);
  int zero = 0;
  // (East steps move north by nanometres through the frame's curvature.)
  for (std::size_t k = 1; k < s.size(); ++k) zero += std::abs(s.axis_m[1][k] - s.axis_m[1][k - 1]) < 1e-6;
  EXPECT_GT(zero, 250);  // north moves < 1.6 cm/s against a 0.185 m quantum
}

TEST(CalibrationLog, TooFewFixesIsAnError) {
  ReceiverLog log = read_receiver_log(test::make_log(1.0, 10, 5, false).text);
  EXPECT_THROW((void)to_enu_series(log), std::invalid_argument);
  ReceiverLog empty = read_receiver_log("garbage\x01\x02 $GPGGA,,,,,,0,,,,,,,,*66\n");
  EXPECT_TRUE(empty.fixes.empty());
  EXPECT_THROW((void)to_enu_series(empty), std::invalid_argument);
}

// Found while fuzzing nmea_log (hundreds of MB per input): 20 fixes at 50 Hz, then times 13 h back
// five times (each taken as a midnight) made a series of 21 million epochs per axis; a damaged log
// could exhaust memory.
TEST(CalibrationLog, ASpanOfDaysIsRefusedNotAllocated) {
  std::string text;
  auto gga = [&text](const std::string& time) {
    text += nmea::frame("GPGGA," + time + ",4304.33935,N,08924.74923,W,1,08,1.0,260.0,M,0.0,M,,");
  };
  for (int i = 0; i < 20; ++i) gga(fmt::format("1200{:05.2f}", i * 0.02));
  for (const int hour : {23, 10, 21, 8, 19, 6, 17, 4, 15, 2}) gga(fmt::format("{:02}0000.00", hour));
  ReceiverLog log = read_receiver_log(text);
  ASSERT_EQ(log.fixes.size(), 30u);
  try {
    (void)to_enu_series(log);
    ADD_FAILURE() << "a span of days at 50 Hz was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("epochs at 50 Hz: calibration takes at most 10000000 epochs"),
              std::string::npos) << e.what();
  }
}

// Issue 22 point 9: a 503 MB log took 7.4 GB to calibrate (the whole file, then every sentence, in
// memory). The reader now takes the file in chunks: fed in pieces of any size, sentences cut
// anywhere, it finds exactly what it finds in the whole text.
TEST(CalibrationLog, ReadingInChunksFindsWhatTheWholeTextHas) {
  const test::MessyLog made = test::make_log(5.0, 400, 6, true);
  const ReceiverLog whole = read_receiver_log(made.text);
  for (const std::size_t chunk : {std::size_t{1}, std::size_t{7}, std::size_t{100}, std::size_t{4096}}) {
    ReceiverLogReader reader;
    for (std::size_t i = 0; i < made.text.size(); i += chunk)
      reader.feed(std::string_view(made.text).substr(i, chunk));
    const ReceiverLog pieces = reader.finish();
    ASSERT_EQ(pieces.fixes.size(), whole.fixes.size()) << chunk;
    for (std::size_t k = 0; k < whole.fixes.size(); ++k) {
      EXPECT_EQ(pieces.fixes[k].time_s, whole.fixes[k].time_s);
      EXPECT_EQ(pieces.fixes[k].position.lat_deg, whole.fixes[k].position.lat_deg);
    }
    EXPECT_EQ(pieces.speeds.size(), whole.speeds.size());
    EXPECT_EQ(pieces.counts.stream.garbage_bytes, whole.counts.stream.garbage_bytes);
    EXPECT_EQ(pieces.counts.repeated_time, whole.counts.repeated_time);
    EXPECT_EQ(pieces.minute_decimals, 6);
  }
}

// The receiver's speeds over ground: the active RMCs' (one a fix here, knots to m/s), else VTG's
// km/h; never both for one epoch.
TEST(CalibrationLog, ReadsTheReportedSpeedOverGround) {
  const test::MessyLog made = test::make_log(1.0, 60, 5, false);
  const ReceiverLog rmc = read_receiver_log(made.text);
  EXPECT_EQ(rmc.speeds.size(), made.fixes);
  EXPECT_EQ(rmc.counts.speed_reports, made.fixes);
  std::string vtg_only;
  for (int i = 0; i < 20; ++i) {
    vtg_only += nmea::frame(fmt::format("GPGGA,1200{:02}.00,4304.33935,N,08924.74923,W,1,08,1.0,260.0,M,0.0,M,,", i));
    vtg_only += nmea::frame("GPVTG,,T,,M,0.214,N,0.396,K,A");
  }
  const ReceiverLog vtg = read_receiver_log(vtg_only);
  ASSERT_EQ(vtg.speeds.size(), 20u);
  EXPECT_NEAR(vtg.speeds[5].speed_mps, 0.396 / 3.6, 1e-6);
  EXPECT_EQ(vtg.speeds[5].time_s, 5.0);
}

// The epoch limit follows the memory: a limit below the log's span is refused with the reason.
TEST(CalibrationLog, TheEpochLimitComesFromTheMemoryAvailable) {
  EXPECT_EQ(max_epochs_for_memory(0), 0u);
  EXPECT_EQ(max_epochs_for_memory(std::uint64_t{1} << 40), kMaxCalibrationEpochs);
  EXPECT_EQ(max_epochs_for_memory(1'000'000'000), 1'000'000'000 / 2 / kCalibrationBytesPerEpoch);
  ReceiverLog log = read_receiver_log(test::make_log(1.0, 300, 5, false).text);
  try {
    (void)to_enu_series(log, 100, "the reason");
    ADD_FAILURE() << "300 epochs went into a limit of 100";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at most 100 epochs of one continuous recording (the reason)"),
              std::string::npos) << e.what();
  }
}

TEST(CalibrationStats, GapsAreLeftOutOfDifferences) {
  const double nan = std::nan("");
  // 0 1 2 _ 10 11 12: the jump across the gap is not a first difference.
  const std::vector<double> x{0, 1, 2, nan, 10, 11, 12};
  const AxisStats s = measure_axis(x, 1.0, x.size());
  EXPECT_DOUBLE_EQ(s.range_m, 12.0);
  EXPECT_DOUBLE_EQ(s.d1_sd_m, 0.0);
  EXPECT_DOUBLE_EQ(s.cgrw.width_d1_m, 0.0);
  const std::vector<double> y{0, 1, 3, 6, 10};
  const noise::CgrwAxis a = measure_cgrw_with_gaps(y), b = noise::measure_cgrw_axis(y);
  EXPECT_DOUBLE_EQ(a.width_m, b.width_m);
  EXPECT_DOUBLE_EQ(a.width_d1_m, b.width_d1_m);
  EXPECT_DOUBLE_EQ(a.width_d2_m, b.width_d2_m);
  EXPECT_DOUBLE_EQ(a.sigma_d2_m, b.sigma_d2_m);
}

TEST(CalibrationStats, AllanDeviationOfWhiteNoiseFallsAsOneOverRootTau) {
  std::vector<double> x;
  std::uint64_t state = 1;
  for (int i = 0; i < 20000; ++i) {  // uniform white noise, variance 1/12
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    x.push_back(static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5);
  }
  const AxisStats s = measure_axis(x, 1.0, 1000);
  ASSERT_TRUE(s.allan_m[0] && s.allan_m[1] && s.allan_m[2]);
  EXPECT_NEAR(*s.allan_m[0], std::sqrt(1.0 / 12.0), 0.01);
  EXPECT_NEAR(*s.allan_m[1] / *s.allan_m[0], 1.0 / std::sqrt(10.0), 0.03);
  EXPECT_NEAR(*s.allan_m[2] / *s.allan_m[0], 0.1, 0.02);
  const AxisStats shorter = measure_axis(std::span<const double>(x).first(250), 1.0, 250);
  EXPECT_FALSE(shorter.allan_m[2]);  // 100 s needs 300 samples
}

}  // namespace log_test
}  // namespace
}  // namespace gpsemu::calibration
