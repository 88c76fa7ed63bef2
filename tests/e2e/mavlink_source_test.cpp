// End to end: the real gpsemu binary with --source mavlink:udp:127.0.0.1:0, --noise none and a
// u-blox M8N writing NMEA and UBX; the test sends SIM_STATE (MAVLink 2) or HIL_STATE_QUATERNION
// frames over loopback at 50 Hz for a vehicle climbing north-east, with other messages and
// garbage between them, the way an autopilot's stream looks. The output shows the position (GGA),
// the speed and course (RMC) and the velocity (NAV-PVT velN/velE; velD once the fix carries a
// vertical velocity) of what was sent; the summary
// at exit counts the frames. Over TCP, gpsemu connects to the test's "simulator", frames come in
// two writes each, and the simulator drops the connection and takes the reconnection. Waits with
// poll() via test::Process, no sleeps but the sender's pacing.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <poll.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "emulator/model/geo.hpp"
#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/mavlink/vehicle_state.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/tcp_listener.hpp"

namespace gpsemu {
namespace {
namespace mavlink_source_test {

using namespace std::chrono;
using sources::mavlink::VehicleState;

const Geodetic kOrigin{43.0725, -89.4125, 260.0};

double realtime_s() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<double>(ts.tv_sec) + ts.tv_nsec * 1e-9;
}

/// 3 m/s north, 4 m/s east (5 m/s at 53.13 degrees), climbing 1 m/s from 20 m above the origin.
struct Climb {
  double t0;
  Enu position(double t) const { return {4.0 * (t - t0), 3.0 * (t - t0), 20.0 + (t - t0)}; }
};
constexpr double kCourseDeg = 53.130102354;

class UdpSender {
 public:
  explicit UdpSender(std::uint16_t port) : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ok_ = connect(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0;
  }
  ~UdpSender() { ::close(fd_); }
  void send(const std::vector<std::uint8_t>& bytes) const { (void)::send(fd_, bytes.data(), bytes.size(), 0); }
  [[nodiscard]] bool ok() const { return ok_; }

 private:
  int fd_;
  bool ok_ = false;
};

struct Output {
  std::vector<nmea::GgaData> gga;
  std::vector<nmea::RmcData> rmc;
  std::vector<std::string> nav_pvt;  ///< payloads
};

Output read_output(const std::string& bytes) {
  Output out;
  ubx::FrameReader reader;
  for (const ubx::ClientMessage& m : reader.feed(bytes)) {
    if (const auto* f = std::get_if<ubx::Frame>(&m)) {
      if (f->id == ubx::msg::nav_pvt) out.nav_pvt.push_back(f->payload);
    } else if (const auto* s = std::get_if<nmea::Sentence>(&m)) {
      if (s->type == "GGA") {
        if (const auto g = nmea::parse_gga(*s)) out.gga.push_back(g.value());
      } else if (s->type == "RMC") {
        if (const auto r = nmea::parse_rmc(*s)) out.rmc.push_back(r.value());
      }
    }
  }
  return out;
}

/// Seconds since 1970 of a time of day in the run that started at `reference_s`.
double epoch_s(milliseconds time_of_day, double reference_s) {
  double t = std::floor(reference_s / 86400.0) * 86400.0 + duration<double>(time_of_day).count();
  if (t < reference_s - 43200.0) t += 86400.0;
  return t;
}

void run_climb(std::uint32_t message_id) {
  const LocalFrame frame(kOrigin);
  const double duration_s = 4.0;
  test::Process gpsemu({GPSEMU_BINARY, "--source", "mavlink:udp:127.0.0.1:0", "--noise", "none", "--rate", "10",
                        "--duration", fmt::format("{}", duration_s), "--protocol", "nmea+ubx", "--receiver",
                        "ublox-m8n", "--output", "stdout", "--log-level", "info"});
  const auto port = test::wait_for_port(gpsemu, "waiting for MAVLink");
  ASSERT_TRUE(port) << gpsemu.stderr_text();
  UdpSender sender(*port);
  ASSERT_TRUE(sender.ok());
  const Climb climb{realtime_s()};
  const std::vector<std::uint8_t> heartbeat =
      sources::mavlink::encode_frame(0, std::vector<std::uint8_t>{0, 0, 0, 0, 2, 3, 0x51, 4, 3});
  double first_s = 0.0, last_s = 0.0;
  const auto start = steady_clock::now();
  for (int i = 0; i < static_cast<int>((duration_s + 0.4) * 50); ++i) {
    gpsemu.pump_until(start + milliseconds(20) * i);
    const double now = realtime_s();
    const Geodetic g = frame.to_geodetic(climb.position(now));
    VehicleState s;
    s.message_id = message_id;
    s.lat_deg = g.lat_deg;
    s.lon_deg = g.lon_deg;
    s.alt_msl_m = g.alt_m;
    s.velocity = sources::mavlink::VelocityNed{3.0, 4.0, -1.0};
    s.yaw_deg = kCourseDeg;
    s.pitch_deg = 8.0;
    s.time_usec = static_cast<std::uint64_t>(now * 1e6);
    std::vector<std::uint8_t> datagram = sources::mavlink::encode_state(s, {.sequence = static_cast<std::uint8_t>(i)});
    if (i % 10 == 0) datagram.insert(datagram.begin(), heartbeat.begin(), heartbeat.end());  // two frames, one datagram
    if (i % 25 == 0) sender.send({'j', 'u', 'n', 'k'});
    sender.send(datagram);
    if (i == 0) first_s = now;
    last_s = now;
  }
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const Output out = read_output(gpsemu.stdout_text());
  EXPECT_EQ(out.gga.size(), 40u);
  EXPECT_EQ(out.rmc.size(), 40u);
  EXPECT_EQ(out.nav_pvt.size(), 40u);

  double worst_h_m = 0.0, worst_v_m = 0.0, worst_speed_mps = 0.0, worst_course_deg = 0.0;
  int compared = 0;
  for (std::size_t k = 0; k < out.gga.size() && k < out.rmc.size(); ++k) {
    const nmea::GgaData& gga = out.gga[k];
    const double t = epoch_s(*gga.time_of_day, first_s);
    if (t < first_s + 0.1 || t > last_s) continue;
    ASSERT_TRUE(gga.lat_deg && gga.lon_deg && gga.alt_msl_m) << "no fix at " << t;
    const Enu got = frame.to_enu({*gga.lat_deg, *gga.lon_deg, *gga.alt_msl_m});
    const Enu truth = climb.position(t);
    worst_h_m = std::max(worst_h_m, std::hypot(got.east_m - truth.east_m, got.north_m - truth.north_m));
    worst_v_m = std::max(worst_v_m, std::abs(got.up_m - truth.up_m));
    const nmea::RmcData& rmc = out.rmc[k];
    EXPECT_TRUE(rmc.status_active);
    worst_speed_mps = std::max(worst_speed_mps, std::abs(rmc.speed_mps.value_or(0.0) - 5.0));
    worst_course_deg = std::max(worst_course_deg, std::abs(rmc.course_deg_true.value_or(0.0) - kCourseDeg));
    ++compared;
  }
  EXPECT_GE(compared, 30);
  EXPECT_LT(worst_h_m, 0.03) << "horizontal error (m): degE7 positions and the NMEA resolution";
  EXPECT_LT(worst_v_m, 0.06) << "vertical error (m); GGA altitude has 0.1 m resolution";
  EXPECT_LT(worst_speed_mps, 0.01) << "RMC speed error (m/s)";
  EXPECT_LT(worst_course_deg, 0.1) << "RMC course error (degrees)";

  int pvt_checked = 0;
  for (const std::string& p : out.nav_pvt) {
    if (ubx::get_u1(p, 20) != 3) continue;  // fixType 3D
    EXPECT_NEAR(ubx::get_i4(p, 48), 3000, 15) << "velN (mm/s)";
    EXPECT_NEAR(ubx::get_i4(p, 52), 4000, 15) << "velE (mm/s)";
    // velD: the truth carries the climb (tests/unit/sources/mavlink_source_test.cpp), but this
    // branch's fix has no vertical velocity yet (ubx/nav.cpp writes velD 0); once it has, -1000.
    const std::int32_t vel_down_mmps = ubx::get_i4(p, 56);
    EXPECT_TRUE(vel_down_mmps == 0 || std::abs(vel_down_mmps + 1000) <= 15) << "velD (mm/s) " << vel_down_mmps;
    ++pvt_checked;
  }
  EXPECT_GE(pvt_checked, 30);
  const std::string log = gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(log, "of others")) << log;
  EXPECT_TRUE(test::contains(log, "garbage_bytes")) << log;
  const std::size_t summary = log.find("pose input mavlink:");
  if (summary != std::string::npos) std::printf("[ info ] %s\n", log.substr(summary, log.find('\n', summary) - summary).c_str());
  std::printf("[ info ] mavlink %u: %d epochs compared, worst horizontal %.1f mm, vertical %.1f mm, speed %.4f m/s, "
              "course %.3f deg\n", message_id, compared, worst_h_m * 1000, worst_v_m * 1000, worst_speed_mps,
              worst_course_deg);
}

TEST(MavlinkEndToEnd, SimStateOverUdpGivesPositionSpeedCourseAndVelocity) {
  run_climb(sources::mavlink::kSimStateId);
}

TEST(MavlinkEndToEnd, HilStateQuaternionOverUdpGivesPositionSpeedCourseAndVelocity) {
  run_climb(sources::mavlink::kHilStateQuaternionId);
}

/// A SIM_STATE frame of the climb at `now`.
std::vector<std::uint8_t> climb_frame(const LocalFrame& frame, const Climb& climb, double now, int i) {
  const Geodetic g = frame.to_geodetic(climb.position(now));
  VehicleState s;
  s.message_id = sources::mavlink::kSimStateId;
  s.lat_deg = g.lat_deg;
  s.lon_deg = g.lon_deg;
  s.alt_msl_m = g.alt_m;
  s.velocity = sources::mavlink::VelocityNed{3.0, 4.0, -1.0};
  s.yaw_deg = kCourseDeg;
  return sources::mavlink::encode_state(s, {.sequence = static_cast<std::uint8_t>(i)});
}

// What gpsemu wrote on connecting, as MAVLink 2 frames checked with the CRC_EXTRA of the common
// set's HEARTBEAT (50) and COMMAND_LONG (152); payloads zero-filled to their full length.
struct WrittenFrame {
  std::uint32_t id = 0;
  std::uint8_t system_id = 0;
  std::vector<std::uint8_t> payload;
};
std::vector<WrittenFrame> read_written_frames(int fd, std::size_t want, milliseconds timeout) {
  std::vector<std::uint8_t> b;
  std::vector<WrittenFrame> frames;
  const auto until = steady_clock::now() + timeout;
  while (frames.size() < want && steady_clock::now() < until) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 50) == 1) {
      std::uint8_t chunk[512];
      const ssize_t n = ::recv(fd, chunk, sizeof chunk, MSG_DONTWAIT);
      if (n <= 0) break;
      b.insert(b.end(), chunk, chunk + n);
    }
    while (b.size() >= 12 && b.size() >= 12u + b[1]) {
      EXPECT_EQ(b[0], 0xFD) << "not a MAVLink 2 frame";
      if (b[0] != 0xFD) return frames;
      const std::size_t len = b[1];
      WrittenFrame f;
      f.id = b[7] | (b[8] << 8) | (b[9] << 16);
      f.system_id = b[5];
      const std::uint8_t extra = f.id == 0 ? 50 : f.id == 76 ? 152 : 0;
      EXPECT_NE(extra, 0) << "unexpected message " << f.id;
      std::uint16_t crc = sources::mavlink::crc_x25(std::span<const std::uint8_t>(b.data() + 1, 9 + len));
      crc = sources::mavlink::crc_x25(extra, crc);
      EXPECT_EQ(crc, b[10 + len] | (b[11 + len] << 8)) << "bad checksum of message " << f.id;
      f.payload.assign(b.begin() + 10, b.begin() + 10 + static_cast<std::ptrdiff_t>(len));
      f.payload.resize(f.id == 76 ? 33 : 9, 0);
      frames.push_back(f);
      b.erase(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(12 + len));
    }
  }
  return frames;
}
float float_at(const std::vector<std::uint8_t>& p, std::size_t at) {
  std::uint32_t u = 0;
  for (int i = 3; i >= 0; --i) u = (u << 8) | p[at + static_cast<std::size_t>(i)];
  return std::bit_cast<float>(u);
}

// On connecting, gpsemu asks the autopilot for its true state as a ground station would (a
// HEARTBEAT, then MAV_CMD_SET_MESSAGE_INTERVAL 511 for SIM_STATE 108 and HIL_STATE_QUATERNION 115
// every 20 000 us): ArduPilot sends SIM_STATE in no default stream.
void expect_state_request(int fd) {
  const std::vector<WrittenFrame> frames = read_written_frames(fd, 3, milliseconds(3000));
  ASSERT_EQ(frames.size(), 3u) << "gpsemu did not ask for the states";
  EXPECT_EQ(frames[0].id, 0u);
  EXPECT_EQ(frames[0].payload[4], 6) << "MAV_TYPE_GCS";
  EXPECT_EQ(frames[0].system_id, 255);
  const float wanted[] = {108.0f, 115.0f};
  for (int i = 0; i < 2; ++i) {
    const WrittenFrame& c = frames[static_cast<std::size_t>(i) + 1];
    ASSERT_EQ(c.id, 76u) << "COMMAND_LONG";
    EXPECT_EQ(c.payload[28] | (c.payload[29] << 8), 511) << "MAV_CMD_SET_MESSAGE_INTERVAL";
    EXPECT_EQ(float_at(c.payload, 0), wanted[i]) << "the message asked for";
    EXPECT_EQ(float_at(c.payload, 4), 20000.0f) << "its interval (us)";
  }
}

TEST(MavlinkEndToEnd, TcpClientReadsFramesSplitOverWritesAndReconnectsWhenTheSimulatorDrops) {
  const LocalFrame frame(kOrigin);
  test::Listener simulator;
  const double duration_s = 5.0;
  test::Process gpsemu({GPSEMU_BINARY, "--source", fmt::format("mavlink:tcp:127.0.0.1:{}", simulator.port()),
                        "--noise", "none", "--rate", "10", "--duration", fmt::format("{}", duration_s), "--output",
                        "stdout", "--log-level", "info"});
  int fd = simulator.accept_one(seconds(20));
  ASSERT_GE(fd, 0) << gpsemu.stderr_text();
  expect_state_request(fd);
  const Climb climb{realtime_s()};
  double first_s = 0.0, drop_s = 0.0, back_s = 0.0, last_s = 0.0;
  const auto start = steady_clock::now();
  for (int i = 0; i < static_cast<int>((duration_s + 0.5) * 50); ++i) {
    gpsemu.pump_until(start + milliseconds(20) * i);
    const double now = realtime_s();
    if (i == 100) {  // the simulator restarts: gpsemu connects again a second later
      ::close(fd);
      fd = -1;
      drop_s = now;
    }
    if (fd < 0 && i > 100) {
      fd = simulator.accept_one(milliseconds(0));
      if (fd >= 0) back_s = now;
    }
    if (fd < 0) continue;
    const std::vector<std::uint8_t> f = climb_frame(frame, climb, now, i);
    (void)::send(fd, f.data(), 17, MSG_NOSIGNAL);  // a frame in two writes
    std::this_thread::sleep_for(milliseconds(1));
    (void)::send(fd, f.data() + 17, f.size() - 17, MSG_NOSIGNAL);
    if (i == 0) first_s = now;
    last_s = now;
  }
  if (fd >= 0) ::close(fd);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  ASSERT_GT(back_s, drop_s) << "gpsemu did not connect again:\n" << gpsemu.stderr_text();
  const Output out = read_output(gpsemu.stdout_text());
  EXPECT_EQ(out.gga.size(), 50u);
  int before = 0, after = 0;
  std::vector<double> error_h_m;
  for (const nmea::GgaData& gga : out.gga) {
    const double t = epoch_s(*gga.time_of_day, first_s);
    const bool in_before = t > first_s + 0.1 && t < drop_s;
    const bool in_after = t > back_s + 0.1 && t < last_s;
    if (!in_before && !in_after) continue;
    ASSERT_TRUE(gga.lat_deg && gga.lon_deg) << "no fix at " << t;
    const Enu got = frame.to_enu({*gga.lat_deg, *gga.lon_deg, gga.alt_msl_m.value_or(0.0)});
    const Enu truth = climb.position(t);
    error_h_m.push_back(std::hypot(got.east_m - truth.east_m, got.north_m - truth.north_m));
    (in_before ? before : after) += 1;
  }
  EXPECT_GE(before, 15);
  EXPECT_GE(after, 10);
  // Over TCP a state holds at its read time (no kernel stamp) and each frame's second half comes
  // 1 ms late: at 5 m/s a few milliseconds of scheduling are centimetres (measured alone: median
  // 8 mm, worst 16-25 mm). A state one frame stale would be 100 mm on every epoch, so the median
  // is held tight; the worst only bounds a scheduling stall on a loaded machine (60 ms = 300 mm),
  // as a sanitizer build running six tests at once can show.
  ASSERT_FALSE(error_h_m.empty());
  std::sort(error_h_m.begin(), error_h_m.end());
  const double median_h_m = error_h_m[error_h_m.size() / 2];
  const double worst_h_m = error_h_m.back();
  EXPECT_LT(median_h_m, 0.04);
  EXPECT_LT(worst_h_m, 0.3);
  const std::string log = gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(log, "closed by the peer; reconnecting every 1000 ms")) << log;
  EXPECT_TRUE(test::contains(log, "2 connections, 1 lost; states asked for on 2 connections")) << log;
  EXPECT_FALSE(test::contains(log, "partial_frame")) << log;
  std::printf("[ info ] mavlink tcp: %d epochs before the drop, %d after (reconnected %.2f s later), median horizontal %.1f mm, worst %.1f mm\n",
              before, after, back_s - drop_s, median_h_m * 1000, worst_h_m * 1000);
}

// ---- a real stream -------------------------------------------------------------------------

/// The records of a .tlog: reception time (microseconds since 1970) and frame.
std::vector<std::pair<std::uint64_t, std::vector<std::uint8_t>>> tlog_records(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> d((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::pair<std::uint64_t, std::vector<std::uint8_t>>> out;
  std::size_t at = 0;
  while (at + 14 <= d.size()) {
    std::uint64_t t_us = 0;
    for (int i = 0; i < 8; ++i) t_us = (t_us << 8) | d[at + static_cast<std::size_t>(i)];
    const std::size_t total = 6 + d[at + 9] + 2;
    out.emplace_back(t_us, std::vector<std::uint8_t>(d.begin() + static_cast<std::ptrdiff_t>(at + 8),
                                                     d.begin() + static_cast<std::ptrdiff_t>(at + 8 + total)));
    at += 8 + total;
  }
  return out;
}

// The ArduPlane SITL capture (tests/data/mavlink/) replayed over UDP at its recorded pace, every
// frame as it came (HEARTBEAT, ATTITUDE, ... and 36 SIMSTATE). The capture is bursty: its SIMSTATEs
// came in bursts a few milliseconds apart, with gaps of 1.1 to 2.2 s between bursts (the ground
// station's link), so gpsemu runs with --pose-timeout 3 to keep the fix across the gaps, and each
// epoch is compared with the path the truth took around it. SIMSTATE has no velocity, so speed
// comes from the track, timed by the ATTITUDE sent before each SIMSTATE (without it, the arrival
// times of bunched frames made that speed wild: 7 to 28 m off the path; with it, 0.25 m).
TEST(MavlinkEndToEnd, ARealArduPilotSitlStreamReplayedOverUdpIsFollowed) {
  const auto records =
      tlog_records(std::filesystem::path(GPSEMU_SOURCE_DIR) / "tests" / "data" / "mavlink" / "ardupilot-sitl-quadplane.tlog");
  ASSERT_EQ(records.size(), 986u);
  const LocalFrame frame(Geodetic{-35.363, 149.165, 584.0});
  test::Process gpsemu({GPSEMU_BINARY, "--source", "mavlink:udp:127.0.0.1:0", "--noise", "none", "--rate", "10",
                        "--duration", "7", "--pose-timeout", "3", "--origin", "-35.363,149.165,584", "--output",
                        "stdout", "--log-level", "info"});
  const auto port = test::wait_for_port(gpsemu, "waiting for MAVLink");
  ASSERT_TRUE(port) << gpsemu.stderr_text();
  UdpSender sender(*port);
  // Truth: SIMSTATE positions at their place in the log, as wall times of this replay.
  std::vector<std::pair<double, Enu>> truth;
  const auto start = steady_clock::now();
  const double start_s = realtime_s();
  for (const auto& [t_us, bytes] : records) {
    const auto offset = microseconds(t_us - records.front().first);
    gpsemu.pump_until(start + offset);  // reading its NMEA meanwhile: a full pipe would stall it
    sender.send(bytes);
    if (bytes[5] != sources::mavlink::kSimstateId) continue;
    sources::mavlink::FrameReader reader;
    reader.feed(bytes);
    const auto state = std::get<VehicleState>(sources::mavlink::decode_state(*reader.next()));
    truth.emplace_back(start_s + duration<double>(offset).count(), frame.to_enu({state.lat_deg, state.lon_deg, 584.0}));
  }
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const Output out = read_output(gpsemu.stdout_text());
  double worst_m = 0.0;
  int compared = 0;
  for (const nmea::GgaData& gga : out.gga) {
    const double t = epoch_s(*gga.time_of_day, start_s);
    if (t < truth.front().first + 0.1 || t > truth.back().first) continue;
    ASSERT_TRUE(gga.lat_deg && gga.lon_deg) << "no fix at " << t;
    const Enu got = frame.to_enu({*gga.lat_deg, *gga.lon_deg, 584.0});
    double nearest_m = 1e9;  // to the truth's samples within 2.5 s of the epoch
    for (const auto& [at, p] : truth) {
      if (std::abs(at - t) <= 2.5) nearest_m = std::min(nearest_m, std::hypot(got.east_m - p.east_m, got.north_m - p.north_m));
    }
    worst_m = std::max(worst_m, nearest_m);
    ++compared;
  }
  EXPECT_GE(compared, 50);
  EXPECT_LT(worst_m, 2.0) << "horizontal distance from the truth's path (m)";
  const std::string log = gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(log, "(SIMSTATE ")) << log;
  EXPECT_TRUE(test::contains(log, "of others")) << log;
  const std::size_t summary = log.find("pose input mavlink:");
  if (summary != std::string::npos) std::printf("[ info ] %s\n", log.substr(summary, log.find('\n', summary) - summary).c_str());
  std::printf("[ info ] ArduPilot SITL replay: %d epochs compared, worst %.2f m from the truth's path\n", compared, worst_m);
}

}  // namespace mavlink_source_test
}  // namespace
}  // namespace gpsemu
