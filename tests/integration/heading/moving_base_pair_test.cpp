// A moving-base pair on a car driving a circle (sim:circle): the base's epochs carry its RTCM3,
// forwarded to the rover as an autopilot does (the whole byte stream, NMEA and all); the client
// turns NAV-RELPOSNED on with CFG-VALSET (and polls it); the rover's heading stays within its
// stated accuracy of the truth's yaw while the car turns, and relPosValid drops once the
// forwarding stops.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include "emulator/heading/moving_base.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/sources/sim.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/relposned.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace moving_base_pair_test {

using namespace std::chrono_literals;
using ubx::test::frames_in;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
const Geodetic kOrigin{43.0725, -89.4125, 260.0};
constexpr double kRadToDeg = 180.0 / M_PI;

ChannelSettings pair_member(heading::Role role, std::uint64_t seed) {
  ChannelSettings s;
  s.origin = kOrigin;
  s.seed = seed;
  s.receiver.quality = nmea::FixQuality::rtk_fixed;
  s.moving_base.role = role;
  s.moving_base.antenna = role == heading::Role::rover ? heading::AntennaOffset{0.55, 0.1, 0.0}
                                                       : heading::AntennaOffset{-0.45, 0.1, -0.05};
  s.moving_base.base_antenna = {-0.45, 0.1, -0.05};
  if (role == heading::Role::rover) {
    ubx::SessionSettings u;
    u.start.model = ReceiverModel::ublox_f9p;
    u.start.measurement_period = 100ms;
    u.start.sentences = {};
    s.protocol = protocol::ublox_protocol(u);
  }
  return s;
}

std::string valset_relposned_on() {
  std::string p;
  ubx::put_u1(p, 0);     // version
  ubx::put_u1(p, 0x01);  // RAM
  ubx::put_u2(p, 0);
  ubx::put_u4(p, *ubx::msgout_key(ubx::msg::nav_relposned, ubx::Port::uart1));
  ubx::put_u1(p, 1);
  return ubx::frame_bytes(ubx::msg::cfg_valset, p);
}

std::optional<ubx::RelPosNedFields> relposned_in(const std::string& bytes) {
  for (const auto& f : frames_in(bytes)) {
    if (f.id == ubx::msg::nav_relposned) return ubx::read_relposned(f.payload);
  }
  return std::nullopt;
}

TEST(MovingBasePair, RoverHeadingFollowsTheTurningCarWithinItsAccuracy) {
  sources::SimOptions sim;
  sim.radius_m = 15.0;
  sim.speed_mps = 3.0;  // 0.2 rad/s: a full turn in 31 s
  Channel base(pair_member(heading::Role::moving_base, 1), kT0);
  Channel rover(pair_member(heading::Role::rover, 2), kT0);
  base.set_source(sources::make_sim_source("circle", sim, base.frame(), kT0));
  rover.set_source(sources::make_sim_source("circle", sim, rover.frame(), kT0));
  auto truth = sources::make_sim_source("circle", sim, base.frame(), kT0);

  rover.client_wrote(valset_relposned_on(), 0);
  const auto acks = frames_in(rover.take_reply(0));
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0].id, ubx::msg::ack_ack);

  int checked = 0, outside_3_sigma = 0;
  double sum_squared_error = 0.0;
  double max_sigma_deg = 0.0;
  for (int k = 0; k < 330; ++k) {  // 33 s: more than a full turn
    const UtcNs t = kT0 + k * 100ms;
    (void)base.step(t);
    if (k > 0) {
      EXPECT_NE(base.bytes().find('\xd3'), std::string::npos);
    }
    rover.client_wrote(base.bytes(), 0);  // the autopilot forwards what the base wrote
    (void)rover.take_reply(0);
    (void)rover.step(t);
    const auto rel = relposned_in(rover.bytes());
    ASSERT_TRUE(rel) << "epoch " << k;
    EXPECT_EQ(rel->version, 1);
    if (k == 0) continue;  // nothing forwarded before the first epoch
    ASSERT_EQ(rel->flags & 0x107u, 0x107u) << "gnssFixOK, diffSoln, relPosValid, relPosHeadingValid at epoch " << k;
    EXPECT_EQ((rel->flags >> 3) & 3u, 2u);  // carrSoln fixed
    EXPECT_EQ(rel->flags & 0x20u, 0x20u);   // isMoving
    const double yaw = *truth->truth_at(t)->yaw_deg;
    // The baseline is 1 m straight ahead (the same `right`): its heading is the yaw.
    const double heading = rel->heading_1e5deg * 1e-5;
    const double sigma = rel->acc_heading_1e5deg * 1e-5;
    max_sigma_deg = std::max(max_sigma_deg, sigma);
    const double error_deg = std::remainder(heading - yaw, 360.0);
    sum_squared_error += error_deg * error_deg;
    if (std::abs(error_deg) > 3.0 * sigma) ++outside_3_sigma;
    const double length_m = (rel->length_cm * 100.0 + rel->hp_length) * 1e-4;
    EXPECT_NEAR(length_m, std::hypot(1.0, 0.05), 0.05);
    ++checked;
  }
  EXPECT_EQ(checked, 329);
  EXPECT_NEAR(max_sigma_deg, std::atan2(0.01, 1.0) * kRadToDeg, 0.01);  // 1 cm over 1 m
  // Within its stated accuracy: the RMS error is accHeading (within 20 %, 5 sigma of the estimate
  // over 329 epochs), and at most 1 % of the epochs are beyond 3 accHeading (0.27 % expected).
  EXPECT_NEAR(std::sqrt(sum_squared_error / checked) / max_sigma_deg, 1.0, 0.2);
  EXPECT_LE(outside_3_sigma, 3);
  EXPECT_GE(rover.moving_base_frames(), 329u);  // a 4072.0 each epoch
  ASSERT_NE(protocol::as_ublox(rover.protocol()), nullptr);
  const ubx::FrameStats& in = protocol::as_ublox(rover.protocol())->session().reader_stats();
  EXPECT_GE(in.rtcm_ok, 3u * 329u);  // 4072.0, MSM4 (one a system), 1230 each epoch
  EXPECT_EQ(in.rtcm_bad_crc, 0u);

  // The autopilot stops forwarding: valid for 1.5 s, then the base is lost.
  int last_valid = -1;
  for (int k = 330; k < 360; ++k) {
    const UtcNs t = kT0 + k * 100ms;
    (void)base.step(t);
    (void)rover.step(t);
    const auto rel = relposned_in(rover.bytes());
    ASSERT_TRUE(rel);
    if (rel->flags & 0x4u) last_valid = k;
    EXPECT_EQ(rel->flags & 0x1u, 0x1u);  // the rover's own fix stays
  }
  // The last frames came in after epoch 328 (stamped with it): valid through 1.5 s later.
  EXPECT_EQ(last_valid, 328 + 15);
}

TEST(MovingBasePair, RelPosNedIsPollable) {
  Channel rover(pair_member(heading::Role::rover, 3), kT0);
  sources::SimOptions sim;
  rover.set_source(sources::make_sim_source("stationary", sim, rover.frame(), kT0));
  rover.client_wrote(ubx::frame_bytes(ubx::msg::nav_relposned, ""), 0);
  (void)rover.step(kT0);
  const auto rel = relposned_in(rover.bytes() + rover.take_reply(0));
  ASSERT_TRUE(rel);
  EXPECT_EQ(rel->flags & 0x4u, 0u);  // no base yet: not valid
  EXPECT_EQ(rel->flags & 0x20u, 0x20u);
}

// A pose's pitch and roll tilt the baseline: relPosD and the length follow the attitude, the
// heading stays the yaw (the baseline is fore-aft).
TEST(MovingBasePair, PitchAndRollTiltTheBaselineNotTheHeading) {
  Channel base(pair_member(heading::Role::moving_base, 4), kT0);
  Channel rover(pair_member(heading::Role::rover, 5), kT0);
  rover.client_wrote(valset_relposned_on(), 0);
  (void)rover.take_reply(0);
  sources::Truth truth;
  truth.yaw_deg = 30.0;
  truth.tilt = {10.0, 5.0};
  const double p = 10.0 / kRadToDeg, r = 5.0 / kRadToDeg;
  // Rover - base in the body: 1 m forward, 0 right, 0.05 m down; its down part turned by pitch and roll.
  const double want_down_m = -std::sin(p) * 1.0 + std::cos(p) * std::cos(r) * 0.05;
  // The heading of the horizontal part: the yaw, turned a little by the 5 cm down part rolled sideways.
  const heading::Ned b = heading::baseline_ned({-0.45, 0.1, -0.05}, {0.55, 0.1, 0.0}, 30.0, 10.0, 5.0);
  EXPECT_NEAR(b.down_m, want_down_m, 1e-12);
  const double want_heading_deg = std::atan2(b.east_m, b.north_m) * kRadToDeg;
  EXPECT_NEAR(want_heading_deg, 30.0, 0.3);
  double sum_down_m = 0.0, sum_heading_deg = 0.0;
  int n = 0;
  for (int k = 0; k < 40; ++k) {
    const UtcNs t = kT0 + k * 100ms;
    (void)base.step(t, truth);
    rover.client_wrote(base.bytes(), 0);
    (void)rover.take_reply(0);
    (void)rover.step(t, truth);
    const auto rel = relposned_in(rover.bytes());
    ASSERT_TRUE(rel);
    if (k == 0) continue;
    ASSERT_EQ(rel->flags & 0x107u, 0x107u) << "epoch " << k;
    const double down_m = (rel->d_cm * 100.0 + rel->hp_d) * 1e-4;
    const double length_m = (rel->length_cm * 100.0 + rel->hp_length) * 1e-4;
    EXPECT_NEAR(down_m, want_down_m, 0.05);  // 5 sigma of the 1 cm noise
    EXPECT_NEAR(length_m, std::hypot(1.0, 0.05), 0.05);
    sum_down_m += down_m;
    sum_heading_deg += std::remainder(rel->heading_1e5deg * 1e-5 - want_heading_deg, 360.0);
    ++n;
  }
  EXPECT_NEAR(sum_down_m / n, want_down_m, 0.01);  // the mean of 39: within 6 sigma
  EXPECT_NEAR(sum_heading_deg / n, 0.0, 0.6);      // 1 cm over 0.98 m: 0.6 degrees 1 sigma each, 0.1 the mean
}

}  // namespace moving_base_pair_test
}  // namespace
}  // namespace gpsemu
