// The MSM4/MSM7 observation encoder (rtk/rtcm3_msm): message numbers, signal ids, each system's epoch
// time field, the lock time indicators of RTCM 10403.3 (DF402, DF407), and payloads whose masks and
// body length the project's decoder accepts; bad input refused.
#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_msm.hpp"

namespace gpsemu::rtk {
namespace {
namespace rtcm3_msm_test {

MsmMessage three_satellites(int msm) {
  MsmMessage m;
  m.gnss = Gnss::glonass;
  m.msm = msm;
  m.station_id = 7;
  m.epoch_time = 123456;
  m.more_follow = true;
  m.signal_ids = msm_signal_ids(Gnss::glonass, true);
  m.satellites = {{.sv_id = 9, .range_m = 21.2e6, .range_rate_mps = -512.3, .cn0_dbhz = 44.0, .lock_ms = 5000, .glonass_channel = -2},
                  {.sv_id = 2, .range_m = 19.4e6, .range_rate_mps = 10.0, .cn0_dbhz = 38.5, .lock_ms = 0, .glonass_channel = -4},
                  {.sv_id = 24, .range_m = 24.9e6, .range_rate_mps = 700.0, .cn0_dbhz = 30.0, .lock_ms = 1u << 30,
                   .glonass_channel = std::nullopt}};
  return m;
}

TEST(Rtcm3Msm, NumbersSignalsAndEpochTimes) {
  EXPECT_EQ(msm_message_type(Gnss::gps, 4), 1074);
  EXPECT_EQ(msm_message_type(Gnss::beidou, 7), 1127);
  EXPECT_EQ(msm_message_type(Gnss::qzss, 4), 1114);
  EXPECT_EQ(msm_gnss_of(nmea::GnssSystem::sbas), std::nullopt);
  EXPECT_EQ(msm_gnss_of(nmea::GnssSystem::galileo), Gnss::galileo);
  EXPECT_EQ(msm_signal_ids(Gnss::gps, true), (std::vector<int>{2, 16}));
  EXPECT_EQ(msm_signal_ids(Gnss::galileo, true), (std::vector<int>{2, 15}));
  EXPECT_EQ(msm_signal_ids(Gnss::beidou, false), (std::vector<int>{2}));
  using namespace std::chrono;
  // Wednesday 2024-05-01 12:00:00 UTC: GPS 3 days 12 h 18 s into the week; BDT 14 s less;
  // GLONASS Wednesday (3), 15:00:00 Moscow time.
  const nmea::UtcTime t = sys_days{year{2024} / 5 / 1} + hours{12};
  EXPECT_EQ(msm_epoch_time(Gnss::gps, t), (3u * 86400u + 12u * 3600u + 18u) * 1000u);
  EXPECT_EQ(msm_epoch_time(Gnss::beidou, t), (3u * 86400u + 12u * 3600u + 4u) * 1000u);
  EXPECT_EQ(msm_epoch_time(Gnss::glonass, t), (3u << 27) | (15u * 3600u * 1000u));
}

TEST(Rtcm3Msm, LockTimeIndicatorsFollowTheTables) {
  EXPECT_EQ(msm_lock_indicator(0), 0u);
  EXPECT_EQ(msm_lock_indicator(31), 0u);
  EXPECT_EQ(msm_lock_indicator(32), 1u);
  EXPECT_EQ(msm_lock_indicator(1000), 5u);     // >= 512 ms
  EXPECT_EQ(msm_lock_indicator(524288), 15u);  // >= 524 288 ms
  EXPECT_EQ(msm_lock_indicator(1u << 31), 15u);
  EXPECT_EQ(msm_lock_indicator_extended(63), 63u);
  EXPECT_EQ(msm_lock_indicator_extended(64), 64u);
  EXPECT_EQ(msm_lock_indicator_extended(100), 82u);    // (100 + 64) / 2
  EXPECT_EQ(msm_lock_indicator_extended(1000), 190u);  // (1000 + 2048) / 16
  EXPECT_EQ(msm_lock_indicator_extended(67108863), 703u);
  EXPECT_EQ(msm_lock_indicator_extended(67108864), 704u);
}

TEST(Rtcm3Msm, PayloadsDecodeWithTheirMasksAndLength) {
  for (const int msm : {4, 7}) {
    const std::string payload = encode_msm_observations(three_satellites(msm));
    const Rtcm3Message m = decode_rtcm3(payload);
    EXPECT_TRUE(m.valid) << msm;
    EXPECT_EQ(m.type, msm == 4 ? 1084 : 1087);
    ASSERT_TRUE(m.msm);
    EXPECT_EQ(m.msm->satellites, 3);
    EXPECT_EQ(m.msm->signals, 2);
    EXPECT_EQ(m.msm->cells, 6);
    EXPECT_TRUE(m.msm->more_follow);
    EXPECT_EQ(m.msm->epoch_time, 123456u);
    EXPECT_EQ(*m.station_id, 7);
    // Header 169 bits + cell mask 6, then 3 x (18 | 36) + 6 x (48 | 80) bits, in whole bytes.
    const std::size_t bits = 169 + 6 + (msm == 4 ? 3 * 18 + 6 * 48 : 3 * 36 + 6 * 80);
    EXPECT_EQ(payload.size(), (bits + 7) / 8);
    // The first satellite's rough range (DF397, satellites in mask order: 2, 9, 24): 19.4e6 m is 64.7 ms.
    BitReader r(payload);
    r.skip(169 + 6);
    EXPECT_EQ(r.u(8), 64u);
  }
}

TEST(Rtcm3Msm, BadInputIsRefused) {
  MsmMessage m = three_satellites(4);
  m.msm = 5;
  EXPECT_THROW((void)encode_msm_observations(m), std::invalid_argument);
  m = three_satellites(7);
  m.satellites[0].sv_id = 65;
  EXPECT_THROW((void)encode_msm_observations(m), std::invalid_argument);
  m = three_satellites(7);
  m.satellites[0].range_m = 0.0;
  EXPECT_THROW((void)encode_msm_observations(m), std::invalid_argument);
  m = three_satellites(4);
  m.signal_ids = {2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24};  // 69 cells
  EXPECT_THROW((void)encode_msm_observations(m), std::invalid_argument);
}

}  // namespace rtcm3_msm_test
}  // namespace
}  // namespace gpsemu::rtk
