// The pose message an external simulator sends (udp:/tcp: sources): one JSON object per UDP
// datagram or per '\n'-terminated TCP line, decoded by a pure function (bytes in, a pose or the
// reason it was refused out). No I/O, no clocks, no logging: unit- and fuzz-tested.
//
//   {"t": 12.34, "x": 1.5, "y": -2.0, "z": 0.3, "ve": 1.0, "vn": 0.0, "vu": 0.0}
//   {"lat": 43.0725, "lon": -89.4125, "alt": 261.2}
//
// Keys (every value a JSON number; no other key is accepted):
//   t            optional  sender time (seconds, any epoch, |t| <= kMaxSenderTimeS; used to drop
//                          reordered datagrams and to compute velocity from the track; the time
//                          base only with --clock lockstep)
//   lat, lon     geodetic position (degrees, WGS84; lat in [-90, 90], lon in [-180, 180])
//   alt          optional  altitude above mean sea level (metres); absent: the origin's altitude
//   x, y         local position, metres East and North of --origin
//   z            optional  metres Up from the origin; absent: 0
//   ve, vn       optional  velocity East and North (metres per second), both or neither
//   vu           optional  velocity Up (metres per second), only with ve/vn; absent: 0
//   yaw_deg      optional  true heading of the vehicle body: degrees clockwise from north,
//                          -360..360 (kept as [0, 360)); absent: no heading (HDT empty, THS V)
//   pitch_deg    optional  pitch of the body, nose up positive, -90..90 degrees; absent: 0
//   roll_deg     optional  roll of the body, right side down positive, -180..180 degrees; absent: 0
//                          (pitch and roll place the antennas: a moving-base baseline's tilt)
// Exactly one of the two position forms. Messages longer than kMaxPoseMessageBytes are refused.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>

#include "emulator/model/enu.hpp"

namespace gpsemu::sources {

/// Longest message accepted (bytes, without the TCP '\n'). A pose is ~100 bytes.
inline constexpr std::size_t kMaxPoseMessageBytes = 4096;

/// Largest magnitude accepted for local coordinates (metres) and velocities (metres per second).
inline constexpr double kMaxLocalCoordinateM = 1.0e7;
inline constexpr double kMaxSpeedMps = 1.0e4;
/// Altitude range accepted (metres above MSL); --origin's altitude is held to it too.
inline constexpr double kMinAltM = -1.0e4;
inline constexpr double kMaxAltM = 1.0e6;
/// Largest |t| accepted (seconds, about 127 years: Unix time or simulation time). A larger value
/// would poison the ordering of later poses, and lockstep's base + t would not be representable.
inline constexpr double kMaxSenderTimeS = 4.0e9;
/// A pose farther from the previous one than kMaxJumpSlackM + kMaxSpeedMps * dt is a jump no
/// vehicle makes (PoseReject::too_fast): interpolating across it would cut through the Earth.
/// The slack absorbs arrival-time jitter of fast vehicles (poses bunched by the network).
inline constexpr double kMaxJumpSlackM = 1000.0;

/// Why a message (or connection) was not used. Counted per reason by the socket source.
enum class PoseReject : std::uint8_t {
  too_large,         ///< datagram or line longer than kMaxPoseMessageBytes
  partial_line,      ///< TCP connection closed in the middle of a line
  not_json,          ///< not valid JSON
  not_object,        ///< valid JSON but not an object
  missing_key,       ///< no position, or half of a pair (lat without lon, ve without vn, vu alone)
  extra_key,         ///< a key outside the table above (typos are caught, not ignored)
  mixed_position,    ///< both lat/lon/alt and x/y/z keys
  not_a_number,      ///< a value that is not a JSON number (string, bool, null, array, object)
  not_finite,        ///< NaN or infinity (Python's json.dumps writes NaN/Infinity) or out of double range
  out_of_range,      ///< latitude outside ±90, longitude outside ±180, altitude, coordinate, speed, |yaw_deg|, |pitch_deg|, |roll_deg| or |t| too large
  out_of_order,      ///< sender time `t` not after the previous pose's (a reordered or repeated datagram)
  too_fast,          ///< farther from the previous pose than kMaxSpeedMps allows (see kMaxJumpSlackM)
  flood,             ///< more than one pose per kMinPoseSpacing: the excess is dropped
  other_sender,      ///< another sender owns the stream (see SocketPoseSource)
  too_many_clients,  ///< a TCP connection beyond the client limit, closed at once
  kernel_overflow,   ///< datagrams the kernel dropped because its receive buffer was full
};
inline constexpr std::size_t kPoseRejectCount = 16;

[[nodiscard]] const char* to_string(PoseReject reason);

/// A geodetic position as sent: degrees and optional metres above MSL.
struct GeodeticPose {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  std::optional<double> alt_msl_m;
};

/// A decoded pose message, before it is placed in time.
struct PoseMessage {
  std::optional<double> sender_time_s;            ///< `t` (seconds), when sent
  std::variant<GeodeticPose, Enu> position;       ///< lat/lon/alt, or x/y/z (metres ENU about the origin)
  std::optional<Enu> velocity_mps;                ///< ve/vn/vu (metres per second ENU), when sent
  std::optional<double> yaw_deg;                  ///< yaw_deg (degrees true, [0, 360)), when sent
  double pitch_deg = 0.0;                         ///< pitch_deg (degrees, -90..90), 0 when not sent
  double roll_deg = 0.0;                          ///< roll_deg (degrees, -180..180), 0 when not sent
};

/// `deg` wrapped into [0, 360).
[[nodiscard]] double wrap_360_deg(double deg);
/// The heading a fraction `f` (0..1) of the way from `a` to `b` (degrees true), the shorter way
/// round, in [0, 360); `a` when either is unknown.
[[nodiscard]] std::optional<double> interpolate_yaw_deg(const std::optional<double>& a,
                                                        const std::optional<double>& b, double f);

/// Either the pose or why it was refused.
using PoseDecodeResult = std::variant<PoseMessage, PoseReject>;

/// Decodes one message (a datagram, or a TCP line without its '\n'; a trailing '\r' is allowed).
/// Never throws, never allocates beyond the JSON parser's own use.
[[nodiscard]] PoseDecodeResult decode_pose(std::string_view bytes) noexcept;

}  // namespace gpsemu::sources
