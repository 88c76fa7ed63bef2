// The value a receiver reports for one epoch: what every sentence formatter reads and every
// parser produces. Plain data with units in every name; no behaviour.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "nmea/sentence_set.hpp"

namespace gpsemu::nmea {

/// UTC time of an epoch, millisecond resolution (NMEA carries at most centiseconds in practice).
using UtcTime = std::chrono::sys_time<std::chrono::milliseconds>;

/// GGA fix quality indicator (field 6).
enum class FixQuality : int {
  none = 0,       ///< no fix: position fields are left empty
  gps = 1,        ///< autonomous GNSS fix
  dgps = 2,       ///< differential (SBAS / DGPS)
  pps = 3,        ///< PPS / precise
  rtk_fixed = 4,  ///< RTK with fixed integer ambiguities
  rtk_float = 5,  ///< RTK float
  estimated = 6,  ///< dead reckoning
};

/// 2-D or 3-D (GSA field 2). A 2-D fix has no usable altitude: GGA leaves it empty. A fix whose
/// dimension is `none` (not set) is written as 3-D.
enum class FixDimension : int { none = 1, two_d = 2, three_d = 3 };

/// Most satellites one Fix carries (fixed-size storage: a Fix never allocates).
inline constexpr std::size_t max_satellites = 64;

/// GNSS of a satellite; values are u-blox gnssId numbers.
enum class GnssSystem : std::uint8_t { gps = 0, sbas = 1, galileo = 2, beidou = 3, qzss = 5, glonass = 6 };

/// One satellite in view (a GSV entry; `used` ones are listed in GSA).
struct SatelliteInView {
  int prn = 0;                   ///< NMEA satellite ID (GPS PRN 1..32)
  int elevation_deg = 0;         ///< elevation above the horizon (degrees), 0..90
  int azimuth_deg = 0;           ///< azimuth (degrees true), 0..359
  std::optional<int> snr_dbhz;   ///< carrier-to-noise density (dB-Hz), 0..99; empty when not tracked
  bool used = false;             ///< used in the navigation solution
  GnssSystem system = GnssSystem::gps;
  int sv_id = 0;  ///< the system's own satellite number (GPS PRN 1..32, SBAS 120..158, Galileo 1..36, BeiDou 1..63, QZSS 1..10, GLONASS slot 1..32)
};

/// UTC's leap seconds as a receiver knows them (the GPS navigation message's UTC parameters).
/// The NMEA time fields read only `in_second_60`; UBX's GPS times (iTOW, week), NAV-TIMEGPS leapS
/// and NAV-TIMELS read the rest. The defaults: 18 s since 2017-01-01, no change announced.
struct LeapSeconds {
  int gps_minus_utc_s = 18;  ///< GPS time minus UTC (seconds)
  /// Inside an inserted leap second: `Fix::time_utc` is the second before it (23:59:59.sss of the
  /// old day) and every time field shows second 60 (23:59:60.sss), the date still the old day.
  bool in_second_60 = false;
  int change_s = 0;  ///< a change announced: +1 a second inserted, -1 one deleted, 0 none
  /// The UTC day at whose end the announced (or, after it, the last) leap second is; empty: the
  /// receiver's default (the end of 2016-12-31).
  std::optional<std::chrono::sys_days> event_day;
  /// Seconds to the event (> 0 to come, 0 now: during second 60, < 0 since); with `event_day`.
  std::int64_t time_to_event_s = 0;
};

/// One epoch of receiver output. When `quality == FixQuality::none` only `time_utc` is
/// meaningful and formatters leave every position, speed and accuracy field empty.
struct Fix {
  UtcTime time_utc{};                          ///< epoch time (UTC)
  FixQuality quality = FixQuality::none;       ///< GGA quality
  FixDimension dimension = FixDimension::none; ///< GSA mode
  double lat_deg = 0.0;      ///< WGS84 latitude, degrees, north positive, [-90, 90]
  double lon_deg = 0.0;      ///< WGS84 longitude, degrees, east positive, [-180, 180)
  double alt_msl_m = 0.0;    ///< altitude above mean sea level (metres)
  double geoid_sep_m = 0.0;  ///< geoid separation: ellipsoid height minus MSL altitude (metres)
  double speed_mps = 0.0;    ///< speed over ground (metres per second)
  std::optional<double> course_deg_true;  ///< course over ground, degrees true [0, 360); empty when unknown
  double vel_up_mps = 0.0;   ///< vertical velocity, up positive (metres per second): UBX velD is its negative
  /// Heading of the vehicle (a dual-antenna receiver's measurement, noise included), degrees true
  /// [0, 360); empty when unknown (HDT empty, THS mode V).
  std::optional<double> heading_deg_true;
  int satellites_used = 0;   ///< satellites used in the solution (GGA field 7)
  double hdop = 0.0;         ///< horizontal dilution of precision
  double vdop = 0.0;         ///< vertical dilution of precision
  double pdop = 0.0;         ///< position dilution of precision
  double tdop = 0.0;         ///< time dilution of precision
  double gdop = 0.0;         ///< geometric dilution of precision
  double sigma_lat_m = 0.0;  ///< 1-sigma latitude error estimate (metres), for GST
  double sigma_lon_m = 0.0;  ///< 1-sigma longitude error estimate (metres), for GST
  double sigma_alt_m = 0.0;  ///< 1-sigma altitude error estimate (metres), for GST
  double range_rms_m = 0.0;  ///< RMS of the pseudorange residuals (metres), GST field 2
  double sigma_speed_mps = 0.0;  ///< 1-sigma horizontal speed error estimate (metres per second): UBX sAcc
  /// Satellites in view; the first `satellites_in_view` entries are valid (GSV, GSA).
  std::array<SatelliteInView, max_satellites> satellites{};
  int satellites_in_view = 0;  ///< valid entries of `satellites`, 0..max_satellites

  /// False while the receiver does not know the time (a cold start before its first satellite):
  /// time and date fields are written empty, as a u-blox does.
  bool time_valid = true;

  /// The leap seconds it reports (a `time` fault's leap second sets these).
  LeapSeconds leap{};

  /// Age of the differential corrections (seconds), GGA field 13; empty without corrections.
  std::optional<double> diff_age_s;
  /// Reference station ID of the corrections, 0..4095, GGA field 14; empty without corrections.
  std::optional<int> diff_station_id;

  [[nodiscard]] bool has_fix() const { return quality != FixQuality::none; }
};

/// NMEA version: 2.3 adds the RMC/GLL/VTG mode indicator; 4.1 adds the RMC navigational status.
enum class NmeaVersion { v2_3, v4_1 };

/// How sentences are written. Validated by the caller's configuration.
struct FormatOptions {
  std::string talker = "GP";  ///< two-letter talker ID: GP (GPS) or GN (multi-constellation)
  int minute_decimals = 5;    ///< decimals of minutes in lat/lon, 1..8 (u-blox: 5, about 1.85 cm)
  int time_decimals = 2;      ///< decimals of seconds in hhmmss.ss, 0..3
  NmeaVersion version = NmeaVersion::v4_1;
  SentenceSet sentences = SentenceSet::ublox_default();  ///< sentence types of each epoch
  /// GSV also lists each satellite's second signal (a dual-band receiver: L2 C, L2 OF, E5b, B2I)
  /// as its own group with the NMEA 4.1 signal ID (4.1 only).
  bool gsv_second_signal = false;
  int alt_decimals = 1;  ///< decimals of the GGA altitude (metres), 0..4 (u-blox: 1; some receivers 2-3)
};

}  // namespace gpsemu::nmea
