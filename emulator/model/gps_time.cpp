#include "emulator/model/gps_time.hpp"

#include <chrono>

namespace gpsemu {

GpsTime gps_time(nmea::UtcTime utc, int gps_minus_utc_s) {
  using namespace std::chrono;
  constexpr sys_days gps_epoch{year{1980} / January / 6};
  const milliseconds since = utc - time_point_cast<milliseconds>(gps_epoch) + seconds{gps_minus_utc_s};
  constexpr milliseconds week = duration_cast<milliseconds>(weeks{1});
  const auto w = since / week;
  return {static_cast<int>(w), static_cast<std::uint32_t>((since - w * week).count())};
}

}  // namespace gpsemu
