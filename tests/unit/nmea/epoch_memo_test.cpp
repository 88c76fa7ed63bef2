// The GSA/GSV text kept between epochs (nmea::SatelliteTextMemo, nmea/epoch.cpp): an epoch written
// with the memo is byte for byte the epoch written without it, whatever changed since the last one
// (an azimuth, a used flag, a DOP, the number of satellites, only the bytes between the fields).
#include <gtest/gtest.h>

#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {
namespace epoch_memo_test {

Fix base_fix() {
  Fix fix;
  fix.time_utc = UtcTime{std::chrono::milliseconds{1714564800000}};
  fix.quality = FixQuality::gps;
  fix.dimension = FixDimension::three_d;
  fix.lat_deg = 43.0725;
  fix.lon_deg = -89.4125;
  fix.alt_msl_m = 260.0;
  fix.hdop = 0.8;
  fix.vdop = 1.1;
  fix.pdop = 1.36;
  const std::vector<SatelliteInView> sats = {
      {1, 24, 270, 36, true, GnssSystem::gps, 1},          {3, 27, 313, 36, true, GnssSystem::gps, 3},
      {10, 17, 152, 33, false, GnssSystem::gps, 10},       {51, 37, 205, 36, true, GnssSystem::sbas, 138},
      {66, 61, 111, 44, true, GnssSystem::glonass, 2},     {67, 57, 331, 44, true, GnssSystem::glonass, 3},
      {5, 40, 100, std::nullopt, false, GnssSystem::galileo, 5}};
  for (std::size_t i = 0; i < sats.size(); ++i) fix.satellites[i] = sats[i];
  fix.satellites_in_view = static_cast<int>(sats.size());
  fix.satellites_used = 5;
  return fix;
}

/// Each fix written with one memo kept across them equals the fix written alone.
void expect_same_text(const std::vector<Fix>& fixes, const FormatOptions& options) {
  SatelliteTextMemo memo;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    std::string with_memo, alone;
    append_epoch(fixes[i], options, with_memo, memo);
    append_epoch(fixes[i], options, alone);
    EXPECT_EQ(with_memo, alone) << "epoch " << i;
  }
}

TEST(SatelliteTextMemo, EveryChangeIsWrittenAsWithoutTheMemo) {
  std::vector<Fix> fixes;
  Fix f = base_fix();
  fixes.push_back(f);
  fixes.push_back(f);  // unchanged
  f.satellites[0].azimuth_deg = 271;  // GSV changes, GSA not
  fixes.push_back(f);
  f.satellites[2].used = true;  // GSA changes
  f.satellites_used = 6;
  fixes.push_back(f);
  f.hdop = 0.81;  // GSA's DOPs
  fixes.push_back(f);
  f.satellites[4].snr_dbhz = 43;  // C/N0
  fixes.push_back(f);
  f.satellites[6].snr_dbhz = 20;  // a C/N0 where there was none
  fixes.push_back(f);
  f.satellites[3].prn = 48;  // another SBAS satellite in the same place
  fixes.push_back(f);
  f.satellites_in_view = 5;  // two fewer: a system gone (GSA by system, GN talker)
  fixes.push_back(f);
  f.satellites_in_view = 7;  // back
  fixes.push_back(f);
  f.quality = FixQuality::none;  // no fix: GSA's type and DOPs
  fixes.push_back(f);
  f.quality = FixQuality::gps;
  f.satellites_in_view = 0;  // nothing in view
  fixes.push_back(f);
  fixes.push_back(base_fix());
  FormatOptions options;
  options.talker = "GN";
  expect_same_text(fixes, options);
  options.gsv_second_signal = true;
  expect_same_text(fixes, options);
}

TEST(SatelliteTextMemo, SatellitesThatDifferOnlyBetweenTheirFieldsKeepTheText) {
  // The same satellites with other bytes in the padding (a copy made field by field may leave any):
  // written alike, and an azimuth changed after that is still seen.
  Fix a = base_fix();
  Fix b = a;
  auto* bytes = reinterpret_cast<unsigned char*>(b.satellites.data());
  for (int i = 0; i < b.satellites_in_view; ++i) {
    SatelliteInView s = b.satellites[static_cast<std::size_t>(i)];
    std::memset(bytes + static_cast<std::size_t>(i) * sizeof(SatelliteInView), 0xA5, sizeof(SatelliteInView));
    SatelliteInView* t = new (&b.satellites[static_cast<std::size_t>(i)]) SatelliteInView;  // members only
    t->prn = s.prn;
    t->elevation_deg = s.elevation_deg;
    t->azimuth_deg = s.azimuth_deg;
    if (s.snr_dbhz) t->snr_dbhz.emplace(*s.snr_dbhz);
    t->used = s.used;
    t->system = s.system;
    t->sv_id = s.sv_id;
  }
  EXPECT_NE(std::memcmp(a.satellites.data(), b.satellites.data(), 7 * sizeof(SatelliteInView)), 0)
      << "the padding differs (or this compiler's SatelliteInView has none)";
  Fix c = b;
  c.satellites[1].elevation_deg = 28;
  FormatOptions options;
  options.talker = "GN";
  expect_same_text({a, b, b, c, a}, options);
}

}  // namespace epoch_memo_test
}  // namespace
}  // namespace gpsemu::nmea
