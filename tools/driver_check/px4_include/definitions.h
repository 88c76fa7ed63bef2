// The platform header PX4-GPSDrivers' gps_helper.h includes (GPS_DEFINITIONS_HEADER), written here
// for the host harness of tools/driver-check: the uORB message structs the u-blox and NMEA drivers
// fill (only the fields they touch, with the types PX4's msg files give them), the clock, sleep and
// logging. PX4's own definitions.h is not used (the project holds no third-party code); this
// header is found first because the harness build puts its directory first on the include path.
#pragma once

#include <cstdint>
#include <cstdio>
#include <ctime>

using gps_abstime = std::uint64_t;

/// Microseconds of CLOCK_MONOTONIC, as PX4's hrt_absolute_time().
inline gps_abstime gps_absolute_time() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<gps_abstime>(ts.tv_sec) * 1000000u + static_cast<gps_abstime>(ts.tv_nsec) / 1000u;
}

inline void gps_usleep(gps_abstime usec) {
  timespec ts{static_cast<time_t>(usec / 1000000u), static_cast<long>((usec % 1000000u) * 1000u)};
  nanosleep(&ts, nullptr);
}

// The drivers' log lines go to stderr, prefixed, one a line (PX4_INFO/PX4_WARN/PX4_ERR).
#define GPS_INFO(...) (std::fprintf(stderr, "px4 INFO: " __VA_ARGS__), std::fputc('\n', stderr))
#define GPS_WARN(...) (std::fprintf(stderr, "px4 WARN: " __VA_ARGS__), std::fputc('\n', stderr))
#define GPS_ERR(...) (std::fprintf(stderr, "px4 ERROR: " __VA_ARGS__), std::fputc('\n', stderr))

#ifndef M_DEG_TO_RAD_F
#define M_DEG_TO_RAD_F 0.0174532925f
#endif
#ifndef M_RAD_TO_DEG_F
#define M_RAD_TO_DEG_F 57.2957795f
#endif

/// uORB sensor_gps: what the drivers write.
struct sensor_gps_s {
  std::uint64_t timestamp;
  std::uint64_t timestamp_sample;
  std::uint64_t time_utc_usec;
  double latitude_deg;
  double longitude_deg;
  double altitude_msl_m;
  double altitude_ellipsoid_m;
  float s_variance_m_s;
  float c_variance_rad;
  float eph;
  float epv;
  float hdop;
  float vdop;
  std::int32_t noise_per_ms;
  std::int32_t jamming_indicator;
  float vel_m_s;
  float vel_n_m_s;
  float vel_e_m_s;
  float vel_d_m_s;
  float cog_rad;
  std::int32_t timestamp_time_relative;
  float heading;
  float heading_offset;
  float heading_accuracy;
  float rtcm_injection_rate;
  std::uint16_t automatic_gain_control;
  std::uint8_t fix_type;
  std::uint8_t jamming_state;
  std::uint8_t spoofing_state;
  bool vel_ned_valid;
  std::uint8_t satellites_used;
  bool rtcm_crc_failed;
  std::uint8_t rtcm_msg_used;
};

/// uORB satellite_info.
struct satellite_info_s {
  static constexpr std::uint8_t SAT_INFO_MAX_SATELLITES = 40;
  std::uint64_t timestamp;
  std::uint8_t count;
  std::uint8_t svid[SAT_INFO_MAX_SATELLITES];
  std::uint8_t used[SAT_INFO_MAX_SATELLITES];
  std::uint8_t elevation[SAT_INFO_MAX_SATELLITES];
  std::uint8_t azimuth[SAT_INFO_MAX_SATELLITES];
  std::uint8_t snr[SAT_INFO_MAX_SATELLITES];
  std::uint8_t prn[SAT_INFO_MAX_SATELLITES];
};

/// uORB sensor_gnss_relative (NAV-RELPOSNED).
struct sensor_gnss_relative_s {
  std::uint64_t timestamp;
  std::uint64_t timestamp_sample;
  std::uint64_t time_utc_usec;
  std::uint16_t reference_station_id;
  float position[3];
  float position_length;
  float heading;
  float heading_accuracy;
  float position_accuracy[3];
  float accuracy_length;
  bool gnss_fix_ok;
  bool differential_solution;
  bool relative_position_valid;
  bool carrier_solution_floating;
  bool carrier_solution_fixed;
  bool moving_base_mode;
  bool reference_position_miss;
  bool reference_observations_miss;
  bool heading_valid;
  bool relative_position_normalized;
};
