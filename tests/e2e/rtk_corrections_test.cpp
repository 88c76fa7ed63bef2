// RTCM3 corrections into a running gpsemu and the RTK state timeline as the vehicle computer sees
// it: a base station stream (1006 + GPS MSM7, the project's encoder, frames RTKLIB's convbin
// reads: tests/integration/rtk) sent to --rtcm udp:PORT while gpsd reads the pty. The GGA written
// goes 1 -> 2 (DGPS) -> 5 (float) -> 4 (fixed), then, when the corrections stop, 4 -> 5 -> 2 -> 1 on
// the --rtk-timeouts timeline, with the correction age and station id in GGA fields 13 and 14;
// gpsd 3.22 reports the states as TPV "status" 2 (DGPS), 4 (RTK float) and 3 (RTK fixed). A frame
// with a bad CRC is dropped and counted in the summary. The same corrections written to an F9P's
// u-blox port (as PX4/ArduPilot inject them) are reported by RXM-RTCM once the client turns it on,
// and NAV-PVT's carrSoln reaches fixed with a correction age; an M9N (DGNSS only) reports them by
// RXM-RTCM too and goes DGPS (NAV-PVT diffSoln, GGA quality 2), never RTK. Short timeline options
// keep it to seconds.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "nmea/parse.hpp"
#include "tests/support/gpsd.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/rtk_rover.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace rtk_corrections_test {

namespace fs = std::filesystem;
using namespace std::chrono;

int udp_sender() { return ::socket(AF_INET, SOCK_DGRAM, 0); }

void send_to(int fd, int port, const std::string& bytes) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  (void)::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
}

struct Epoch {
  std::int64_t ms = 0;
  int quality = 0;
  std::string age, station;  // GGA fields 13 and 14
};

std::vector<Epoch> gga_epochs(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  std::vector<Epoch> out;
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(text.str())) {
    if (s.type != "GGA") continue;
    const auto gga = nmea::parse_gga(s);
    if (!gga.ok() || !gga->time_of_day) continue;
    Epoch e{gga->time_of_day->count(), static_cast<int>(gga->quality), "", ""};
    if (s.fields.size() >= 14) {
      e.age = s.fields[12];
      e.station = s.fields[13];
    }
    out.push_back(e);
  }
  return out;
}

TEST(RtkCorrections, UdpStreamDrivesTheTimelineThatGpsdReports) {
  const fs::path dir = test::scratch_root() / fmt::format("gpsemu_rtk_{}", ::getpid());
  fs::create_directories(dir);
  const fs::path link = dir / "gps", file = dir / "out.nmea";
  const int rtcm_port = test::free_tcp_port();  // free for UDP too, almost always
  test::Process gpsemu({GPSEMU_BINARY, "--output", "pty:" + link.string(), "--output", "file:" + file.string(),
                        "--rate", "5", "--duration", "7", "--rtcm", fmt::format("udp:{}", rtcm_port),
                        "--rtk-convergence", "0.5,1.5,0", "--rtk-timeouts", "0.5,1.1,1.7", "--log-level", "info"});
  test::GpsdWatch gpsd(gpsemu, link, test::GpsdAccess::read_only);
  ASSERT_TRUE(gpsd.ok()) << gpsd.error();

  // Corrections at 10 Hz for 3 s from 1 s into the run, then silence; one frame with a bad CRC.
  std::set<int> statuses;
  std::thread base([rtcm_port] {
    const int fd = udp_sender();
    std::this_thread::sleep_for(milliseconds(1000));
    std::string bad = test::base_1006();
    bad[6] = static_cast<char>(bad[6] ^ 0x40);
    send_to(fd, rtcm_port, bad);
    for (int k = 0; k < 30; ++k) {
      send_to(fd, rtcm_port, test::base_epoch(k));
      std::this_thread::sleep_for(milliseconds(100));
    }
    ::close(fd);
  });
  gpsd.read_reports(milliseconds(7500), [&](const nlohmann::json& j) {
    if (j["class"] == "TPV" && j.value("mode", 0) >= 2) statuses.insert(j.value("status", 1));
  });
  base.join();
  gpsd.close_client();
  EXPECT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  gpsd.stop();

  const std::vector<Epoch> epochs = gga_epochs(file);
  ASSERT_GT(epochs.size(), 25u);
  // The distinct states in order, and where each began.
  std::vector<int> states;
  std::vector<std::size_t> began;
  for (std::size_t i = 0; i < epochs.size(); ++i) {
    if (states.empty() || states.back() != epochs[i].quality) {
      states.push_back(epochs[i].quality);
      began.push_back(i);
    }
  }
  ASSERT_EQ(states, (std::vector<int>{1, 2, 5, 4, 5, 2, 1})) << gpsemu.stderr_text();
  // Convergence counts from the first MSM: float 0.5 s (3 epochs at 5 Hz), fixed 1.5 s (8) after it.
  EXPECT_EQ(began[2] - began[1], 3u);
  EXPECT_EQ(began[3] - began[1], 8u);
  // Decay after the last MSM (epoch began[4] - 3 at the latest): float, DGPS, none at ages > 0.5,
  // 1.1, 1.7 s: 3 epochs of float, 3 of DGPS.
  EXPECT_EQ(began[5] - began[4], 3u);
  EXPECT_EQ(began[6] - began[5], 3u);
  for (const Epoch& e : epochs) {
    if (e.quality == 1) {
      EXPECT_EQ(e.age, "");
      EXPECT_EQ(e.station, "");
    } else {
      EXPECT_EQ(e.station, "0042");
      EXPECT_FALSE(e.age.empty());
    }
  }
  // gpsd 3.22: status 2 DGPS, 3 RTK fixed, 4 RTK float.
  EXPECT_TRUE(statuses.contains(2)) << "gpsd saw no DGPS";
  EXPECT_TRUE(statuses.contains(3)) << "gpsd saw no RTK fixed";
  EXPECT_TRUE(statuses.contains(4)) << "gpsd saw no RTK float";
  EXPECT_NE(gpsemu.stderr_text().find("1 bad CRC dropped"), std::string::npos) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("1077 x30"), std::string::npos) << gpsemu.stderr_text();
  fs::remove_all(dir);
}

TEST(RtkCorrections, InjectedThroughTheUbloxPortAnF9pReportsRxmRtcmAndReachesFixed) {
  test::RoverClient client;
  client.setup = ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x02\x32\x01", 3));  // RXM-RTCM on
  client.epochs = 25;
  const test::RoverRun run = test::run_f9p_rover("rxm_rtcm", "4", client);
  int rxm_1006 = 0, rxm_1077 = 0, fixed_with_age = 0;
  bool float_seen = false;
  for (const ubx::Frame& f : ubx::test::frames_in(run.bytes)) {
    if (f.id == ubx::msg::rxm_rtcm && f.payload.size() == 8) {
      EXPECT_EQ(ubx::get_u2(f.payload, 4), 42u);
      rxm_1006 += ubx::get_u2(f.payload, 6) == 1006;
      rxm_1077 += ubx::get_u2(f.payload, 6) == 1077;
    }
    if (f.id == ubx::msg::nav_pvt && f.payload.size() == 92) {
      const unsigned carr = ubx::get_u1(f.payload, 21) >> 6;
      float_seen = float_seen || carr == 1;
      if (carr == 2 && ((ubx::get_u2(f.payload, 78) >> 1) & 0x0F) >= 1) ++fixed_with_age;
    }
  }
  EXPECT_GE(rxm_1006, 20) << run.log;
  EXPECT_EQ(rxm_1006, rxm_1077);
  EXPECT_TRUE(float_seen);
  EXPECT_GE(fixed_with_age, 3) << run.log;
  EXPECT_NE(run.log.find("RTCM3 frames (0 bad CRC)"), std::string::npos) << run.log;
}

// A NEO-M9N (SPG 4.04) takes RTCM3 for DGNSS: diffSoln and GGA quality 2 with the correction age
// and station, carrSoln 0 however long the corrections come (RTK float/fixed is the F9P's).
TEST(RtkCorrections, InjectedThroughTheUbloxPortAnM9nReportsRxmRtcmAndGoesDgpsNotRtk) {
  test::RoverClient client;
  client.setup = ubx::frame_bytes(ubx::msg::cfg_valset, ubx::test::valset({{0x20910269, 1}}));  // RXM-RTCM UART1
  client.epochs = 25;  // 2.5 s of corrections: past the 1.0 s the F9P needs for fixed
  const test::RoverRun run = test::run_rover("ublox-m9n", "nmea+ubx", "m9n_dgnss", "4", client);
  int acks = 0, naks = 0, rxm_1077 = 0, pvt_diff = 0, pvt_carrier = 0, gga_dgps = 0, gga_rtk = 0;
  for (const ubx::Frame& f : ubx::test::frames_in(run.bytes)) {
    acks += f.id == ubx::msg::ack_ack;
    naks += f.id == ubx::msg::ack_nak;
    if (f.id == ubx::msg::rxm_rtcm && f.payload.size() == 8 && ubx::get_u2(f.payload, 6) == 1077) {
      EXPECT_EQ(ubx::get_u1(f.payload, 1), 2u << 1);  // msgUsed 2: used
      ++rxm_1077;
    }
    if (f.id == ubx::msg::nav_pvt && f.payload.size() == 92) {
      pvt_diff += (ubx::get_u1(f.payload, 21) & 0x02) != 0;
      pvt_carrier += (ubx::get_u1(f.payload, 21) >> 6) != 0;
    }
  }
  std::istringstream lines(run.bytes);
  for (std::string line; std::getline(lines, line);) {
    const auto at = line.find("GGA,");
    if (at == std::string::npos || at < 3) continue;
    std::vector<std::string> fields;
    std::stringstream ss(line.substr(at));
    for (std::string field; std::getline(ss, field, ',');) fields.push_back(field);
    if (fields.size() < 15) continue;
    gga_dgps += fields[6] == "2" && fields[14].rfind("0042", 0) == 0;
    gga_rtk += fields[6] == "4" || fields[6] == "5";
  }
  // The VALSET took: no NAK, and the RXM-RTCM reports below. (Its ACK can go out before gpsemu
  // counts the freshly opened pty as read, so it is not counted here.)
  EXPECT_LE(acks, 1) << run.log;
  EXPECT_EQ(naks, 0);
  EXPECT_GE(rxm_1077, 20) << run.log;
  EXPECT_GE(pvt_diff, 8) << run.log;
  EXPECT_EQ(pvt_carrier, 0);
  EXPECT_GE(gga_dgps, 8) << run.log;
  EXPECT_EQ(gga_rtk, 0);
  EXPECT_EQ(run.log.find("RTK float"), std::string::npos) << run.log;
}

}  // namespace rtk_corrections_test
}  // namespace
}  // namespace gpsemu
