// The RTK part of a receiver channel with a real UDP socket (--rtcm udp:0): corrections sent to it
// lift the fix to DGPS, float and fixed on the timeline, the position error shrinks by the ratio
// of the quality scales (the truth stays where it is), accuracies follow with their floors, GGA's
// differential fields are filled; a configured quality at least as good is kept; bad CRCs and
// message types are counted in the summary.
#include "emulator/pipeline/rtk_receiver.hpp"

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <GeographicLib/Geocentric.hpp>

#include "emulator/model/receiver.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"

namespace gpsemu {
namespace {
namespace rtk_receiver_test {

using namespace std::chrono;

const Geodetic kOrigin{47.0, 8.0, 400.0};

int port_of(const std::string& described) { return std::stoi(described.substr(described.rfind(':') + 1)); }

/// From one socket, as a base station sends (str2str's udpcli): --rtcm udp: takes the first sender
/// of a good frame as the base and drops other senders' datagrams until it is quiet 2 s.
void send_to(int port, const std::string& bytes) {
  static const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a),
            static_cast<ssize_t>(bytes.size()));
}

std::string corrections() {
  rtk::BasePosition b;
  b.station_id = 7;
  GeographicLib::Geocentric::WGS84().Forward(kOrigin.lat_deg, kOrigin.lon_deg + 0.001, 440.0, b.ecef_x_m, b.ecef_y_m,
                                             b.ecef_z_m);
  return rtk::rtcm3_frame_bytes(rtk::encode_base_position(b, false)) +
         rtk::rtcm3_frame_bytes(rtk::encode_msm(1074, 7, 0, 8, 2));
}

// A fix 1 m east and 2 m up of the truth at the origin, as the receiver model writes it.
nmea::Fix fix_off_truth(const LocalFrame& frame, nmea::FixQuality q, UtcNs t) {
  nmea::Fix fix;
  fix.time_utc = floor<milliseconds>(t);
  fix.quality = q;
  const Geodetic p = frame.to_geodetic({1.0, 0.0, 2.0});
  fix.lat_deg = p.lat_deg;
  fix.lon_deg = p.lon_deg;
  fix.alt_msl_m = p.alt_m;
  fix.geoid_sep_m = 47.0;
  fix.sigma_lat_m = fix.sigma_lon_m = 1.0;
  fix.sigma_alt_m = 1.5;
  fix.range_rms_m = 1.0;
  return fix;
}

// Services the socket until a message arrived (the datagram may take a moment).
void service_until_counted(RtkReceiver& rtk, std::uint64_t messages) {
  for (int i = 0; i < 200 && rtk.counts().messages < messages; ++i) {
    rtk.service();
    ::poll(nullptr, 0, 5);
  }
  ASSERT_GE(rtk.counts().messages, messages);
}

TEST(RtkReceiverUdp, CorrectionsLiftTheFixAndShrinkItsError) {
  rtk::RtkTimeline timeline;  // float after 3 s, fixed after 10 s + 2 s/km
  RtkReceiver rtk(timeline, transport::parse_rtcm_input_spec("udp:0"));
  const LocalFrame frame(kOrigin);
  const std::optional<Enu> truth = Enu{0.0, 0.0, 0.0};
  const UtcNs t0 = sys_days{year{2026} / November / 26} + hours{10};
  nmea::Fix before = fix_off_truth(frame, nmea::FixQuality::gps, t0);
  rtk.apply(t0, before, truth, frame);
  EXPECT_EQ(before.quality, nmea::FixQuality::gps);
  EXPECT_FALSE(before.diff_age_s.has_value());

  std::string bad = corrections();
  bad[4] = static_cast<char>(bad[4] ^ 0x01);
  send_to(port_of(rtk.input()), bad);
  send_to(port_of(rtk.input()), corrections());
  service_until_counted(rtk, 2);
  nmea::Fix dgps = fix_off_truth(frame, nmea::FixQuality::gps, t0 + seconds(1));
  rtk.apply(t0 + seconds(1), dgps, truth, frame);
  EXPECT_EQ(dgps.quality, nmea::FixQuality::dgps);
  EXPECT_EQ(dgps.diff_station_id, 7);
  ASSERT_TRUE(dgps.diff_age_s.has_value());
  EXPECT_DOUBLE_EQ(*dgps.diff_age_s, 0.0);
  const Enu e = frame.to_enu({dgps.lat_deg, dgps.lon_deg, dgps.alt_msl_m});
  EXPECT_NEAR(e.east_m, 0.4, 1e-6);  // 1 m x 0.4 / 1
  EXPECT_NEAR(e.up_m, 0.8, 1e-6);
  EXPECT_NEAR(dgps.sigma_lat_m, 0.4, 1e-9);

  // Keep the corrections coming once a second: fixed after 10 s + 2 s/km x ~76 m.
  nmea::Fix last;
  for (int s = 2; s <= 12; ++s) {
    send_to(port_of(rtk.input()), corrections());
    service_until_counted(rtk, 2 * static_cast<std::uint64_t>(s));
    last = fix_off_truth(frame, nmea::FixQuality::gps, t0 + seconds(s));
    rtk.apply(t0 + seconds(s), last, truth, frame);
    if (s == 4) {
      EXPECT_EQ(last.quality, nmea::FixQuality::rtk_float) << s;
    }
  }
  EXPECT_EQ(last.quality, nmea::FixQuality::rtk_fixed);
  const Enu fixed_e = frame.to_enu({last.lat_deg, last.lon_deg, last.alt_msl_m});
  EXPECT_NEAR(fixed_e.east_m, 0.01, 1e-6);
  EXPECT_NEAR(last.sigma_lat_m, 0.01, 1e-9);  // 1 m x 0.01, the fixed floor
  const std::string summary = rtk.summary(0);
  EXPECT_NE(summary.find("1005 x12"), std::string::npos) << summary;
  EXPECT_NE(summary.find("1 bad CRC dropped"), std::string::npos) << summary;
  EXPECT_EQ(rtk.counts().stream_bad_crc, 1u);
}

TEST(RtkReceiverUdp, AConfiguredQualityAsGoodIsKeptWithTheDifferentialFields) {
  RtkReceiver rtk({}, transport::parse_rtcm_input_spec("udp:0"));
  const LocalFrame frame(kOrigin);
  const UtcNs t0 = sys_days{year{2026} / November / 26} + hours{10};
  send_to(port_of(rtk.input()), corrections());
  service_until_counted(rtk, 2);
  nmea::Fix fix = fix_off_truth(frame, nmea::FixQuality::rtk_fixed, t0);
  const nmea::Fix as_configured = fix;
  rtk.apply(t0, fix, Enu{}, frame);
  EXPECT_EQ(fix.quality, nmea::FixQuality::rtk_fixed);
  EXPECT_DOUBLE_EQ(fix.lat_deg, as_configured.lat_deg);
  EXPECT_EQ(fix.diff_station_id, 7);
}

}  // namespace rtk_receiver_test
}  // namespace
}  // namespace gpsemu
