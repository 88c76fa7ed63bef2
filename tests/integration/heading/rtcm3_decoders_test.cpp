// The moving base's RTCM3, read by real decoders: gpsd's gpsdecode (frames, CRC-24Q, lengths,
// message types, 1230 decoded) and RTKLIB's convbin (the MSM4 observations decoded to RINEX: one
// epoch a second, every tracked satellite with a pseudorange a satellite can have).
#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <string>
#include <vector>

#include "emulator/rtk/rtcm3_reader.hpp"
#include "emulator/model/receiver_models.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/sources/sim.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace rtcm3_decoders_test {

using namespace std::chrono_literals;

constexpr int kEpochs = 10;

struct BaseRun {
  std::string bytes;
  std::vector<int> types;       ///< message types written, in order
  std::vector<int> msm_sats;    ///< satellites in the MSM4s of each epoch
};

BaseRun run_base() {
  const UtcNs t0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
  ChannelSettings s;
  s.origin = {43.0725, -89.4125, 260.0};
  s.receiver.tracking = facts_of(ReceiverModel::ublox_f9p).tracking;  // GPS, GLONASS, Galileo, BeiDou
  s.receiver.quality = nmea::FixQuality::rtk_fixed;
  s.format.sentences = {};  // the RTCM3 alone
  s.moving_base.role = heading::Role::moving_base;
  Channel base(s, t0);
  sources::SimOptions sim;
  base.set_source(sources::make_sim_source("circle", sim, base.frame(), t0));
  BaseRun run;
  rtk::Rtcm3Reader reader;
  for (int k = 0; k < kEpochs; ++k) {
    const nmea::Fix fix = base.step(t0 + k * 1s).fix;
    run.bytes += base.bytes();
    for (const rtk::Rtcm3Frame& f : reader.feed(base.bytes())) run.types.push_back(f.message_type());
    int sats = 0;
    for (int i = 0; i < fix.satellites_in_view; ++i) {
      const auto& sat = fix.satellites[static_cast<std::size_t>(i)];
      if (sat.snr_dbhz && sat.system != nmea::GnssSystem::sbas) ++sats;
    }
    run.msm_sats.push_back(sats);
  }
  return run;
}

TEST(Rtcm3Decoders, GpsdecodeReadsEveryFrame) {
  const BaseRun run = run_base();
  ASSERT_GE(run.types.size(), static_cast<std::size_t>(kEpochs * 4));
  const auto dir = test::scratch_dir("rtcm3", "gpsdecode");
  const auto file = test::write_file(dir / "base.rtcm3", run.bytes);
  const auto r = test::run({"/bin/sh", "-c", "gpsdecode -j < '" + file.string() + "'"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::vector<int> decoded;
  std::istringstream lines(r.out);
  int bias_messages = 0;
  for (std::string line; std::getline(lines, line);) {
    ASSERT_TRUE(test::contains(line, "\"class\":\"RTCM3\"")) << line;
    const auto at = line.find("\"type\":");
    ASSERT_NE(at, std::string::npos) << line;
    decoded.push_back(std::stoi(line.substr(at + 7)));
    if (decoded.back() == 1230) {
      EXPECT_TRUE(test::contains(line, "\"station_id\":0")) << line;
      ++bias_messages;
    }
  }
  EXPECT_EQ(decoded, run.types);  // every frame, none with a bad CRC or length
  EXPECT_EQ(bias_messages, kEpochs);
}

TEST(Rtcm3Decoders, ConvbinDecodesTheObservations) {
  const BaseRun run = run_base();
  const auto dir = test::scratch_dir("rtcm3", "convbin");
  const auto file = test::write_file(dir / "base.rtcm3", run.bytes);
  const auto obs = dir / "base.obs";
  const auto r = test::run({"/usr/bin/convbin", "-r", "rtcm3", "-tr", "2024/05/01", "12:00:00", "-o", obs.string(), file.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream text(test::read_file(obs));
  int epoch = -1, satellites = 0;
  std::vector<int> per_epoch;
  bool header = true;
  for (std::string line; std::getline(text, line);) {
    if (header) {
      header = !test::contains(line, "END OF HEADER");
      continue;
    }
    if (line.rfind("> ", 0) == 0) {
      if (epoch >= 0) per_epoch.push_back(satellites);
      ++epoch;
      satellites = 0;
      // RINEX in GPS time: UTC + 18 s (every system's epoch time, GLONASS's Moscow time too, lands on it)
      const int second = 18 + epoch;
      EXPECT_EQ(line.substr(2, 19), "2024 05 01 12 00 " + std::to_string(second)) << line;
      continue;
    }
    ASSERT_GE(line.size(), 17u) << line;
    const double pseudorange_m = std::stod(line.substr(3, 14));
    EXPECT_GT(pseudorange_m, 1.9e7) << line;  // 64..140 ms of light: MEO and GEO satellites
    EXPECT_LT(pseudorange_m, 4.2e7) << line;
    ++satellites;
  }
  per_epoch.push_back(satellites);
  EXPECT_EQ(per_epoch, run.msm_sats);
}

}  // namespace rtcm3_decoders_test
}  // namespace
}  // namespace gpsemu
