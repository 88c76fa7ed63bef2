// The moving base's RTCM 3 epoch: 4072.0, one MSM4 per system with the multiple-message bit on all
// but the last, then 1230, read back bit by bit (the framing itself: tests/unit/rtk).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "emulator/heading/rtcm3_base.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::heading {
namespace {
namespace rtcm3_test {

/// Reads big-endian bit fields, as RTCM 3 lays them out.
class BitReader {
 public:
  explicit BitReader(std::string bytes) : bytes_(std::move(bytes)) {}
  std::uint64_t get(int bits) {
    std::uint64_t v = 0;
    for (int i = 0; i < bits; ++i, ++pos_) {
      const auto byte = static_cast<unsigned char>(bytes_.at(pos_ / 8));
      v = (v << 1) | ((byte >> (7 - pos_ % 8)) & 1u);
    }
    return v;
  }

 private:
  std::string bytes_;
  std::size_t pos_ = 0;
};

/// The payloads of the frames in `bytes`, in order.
std::vector<std::string> payloads(const std::string& bytes) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at + 6 <= bytes.size()) {
    EXPECT_EQ(static_cast<unsigned char>(bytes[at]), 0xD3);
    const std::size_t len = (static_cast<std::size_t>(bytes[at + 1] & 0x03) << 8) | static_cast<unsigned char>(bytes[at + 2]);
    out.push_back(bytes.substr(at + 3, len));
    at += len + 6;
  }
  EXPECT_EQ(at, bytes.size());
  return out;
}

/// The message numbers of the checked frames in `bytes`, read by the u-blox input's RTCM3 reader.
std::vector<int> message_types(const std::string& bytes, rtk::Rtcm3Reader& reader) {
  std::vector<int> out;
  for (const rtk::Rtcm3Frame& f : reader.feed(bytes)) out.push_back(f.message_type());
  return out;
}

nmea::Fix base_fix() {
  nmea::Fix fix;
  fix.quality = nmea::FixQuality::rtk_fixed;
  fix.dimension = nmea::FixDimension::three_d;
  fix.lat_deg = 43.0725;
  fix.lon_deg = -89.4125;
  fix.alt_msl_m = 260.0;
  fix.geoid_sep_m = -33.0;
  fix.time_utc = nmea::UtcTime{std::chrono::sys_days{std::chrono::year{2024} / 5 / 1}} + std::chrono::hours{12};
  const struct {
    nmea::GnssSystem system;
    int sv;
    int elevation;
    std::optional<int> snr;
  } sats[] = {{nmea::GnssSystem::gps, 5, 60, 45},   {nmea::GnssSystem::gps, 12, 15, 38},
              {nmea::GnssSystem::gps, 30, 40, std::nullopt},  // not tracked: not sent
              {nmea::GnssSystem::galileo, 3, 80, 47}, {nmea::GnssSystem::glonass, 7, 30, 40},
              {nmea::GnssSystem::sbas, 131, 35, 42}};  // no MSM for SBAS here
  for (const auto& s : sats) {
    auto& v = fix.satellites[static_cast<std::size_t>(fix.satellites_in_view++)];
    v.system = s.system;
    v.sv_id = s.sv;
    v.prn = s.sv;
    v.elevation_deg = s.elevation;
    v.snr_dbhz = s.snr;
  }
  return fix;
}

TEST(Rtcm3Base, OneEpochIs4072ThenMsm4PerSystemThen1230) {
  const std::string bytes = base_rtcm3_epoch(base_fix(), 0);
  rtk::Rtcm3Reader reader;
  EXPECT_EQ(message_types(bytes, reader), (std::vector<int>{4072, 1074, 1084, 1094, 1230}));
  EXPECT_EQ(reader.stats().bad_crc, 0u);
  EXPECT_EQ(reader.stats().garbage_bytes, 0u);
  const auto p = payloads(bytes);
  ASSERT_EQ(p.size(), 5u);
  BitReader t4072(p[0]);
  EXPECT_EQ(t4072.get(12), 4072u);
  EXPECT_EQ(t4072.get(12), 0u);  // sub-type 0
  // GPS MSM4: two tracked satellites (5 and 12), one signal (1C), more messages follow.
  BitReader gps(p[1]);
  EXPECT_EQ(gps.get(12), 1074u);
  EXPECT_EQ(gps.get(12), 0u);
  EXPECT_EQ(gps.get(30), (3u * 86400u + 12u * 3600u + 18u) * 1000u);
  EXPECT_EQ(gps.get(1), 1u);  // multiple message bit
  (void)gps.get(3 + 7 + 2 + 2 + 1 + 3);
  EXPECT_EQ(gps.get(64), (1ull << (64 - 5)) | (1ull << (64 - 12)));
  EXPECT_EQ(gps.get(32), 1ull << 30);
  EXPECT_EQ(gps.get(2), 3u);  // cell mask
  const auto ms5 = gps.get(8), ms12 = gps.get(8);
  EXPECT_GE(ms5, 67u);  // 20 200 km up at 60 degrees: ~68 ms
  EXPECT_LE(ms5, 70u);
  EXPECT_GT(ms12, ms5);  // lower: farther
  EXPECT_LE(ms12, 86u);
  BitReader galileo(p[3]);
  EXPECT_EQ(galileo.get(12), 1094u);
  (void)galileo.get(12 + 30);
  EXPECT_EQ(galileo.get(1), 0u);  // the last MSM of the epoch
  BitReader t1230(p[4]);
  EXPECT_EQ(t1230.get(12), 1230u);
  EXPECT_TRUE(base_rtcm3_epoch(nmea::Fix{}, 0).empty());  // no fix, no corrections
}

}  // namespace rtcm3_test
}  // namespace
}  // namespace gpsemu::heading
