#include "emulator/sources/mavlink/vehicle_state.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace gpsemu::sources::mavlink {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// Little-endian readers and writers of a payload (the wire is little-endian whatever the host).
template <typename T>
T get(const Frame& f, std::size_t at) {
  using U = std::conditional_t<sizeof(T) == 2, std::uint16_t, std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
  U u = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) u |= static_cast<U>(static_cast<U>(f.payload[at + i]) << (8 * i));
  return std::bit_cast<T>(u);
}
double get_f(const Frame& f, std::size_t at) { return static_cast<double>(get<float>(f, at)); }

template <typename T>
void put(std::vector<std::uint8_t>& p, std::size_t at, T value) {
  using U = std::conditional_t<sizeof(T) == 2, std::uint16_t, std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
  const U u = std::bit_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) p[at + i] = static_cast<std::uint8_t>(u >> (8 * i));
}
void put_f(std::vector<std::uint8_t>& p, std::size_t at, double value) { put(p, at, static_cast<float>(value)); }

/// Degrees from a degE7 integer.
double from_e7(std::int32_t v) { return static_cast<double>(v) * 1e-7; }
std::int32_t to_e7(double deg) { return static_cast<std::int32_t>(std::llround(deg * 1e7)); }

double wrap_180_deg(double deg) {
  const double w = wrap_360_deg(deg);
  return w > 180.0 ? w - 360.0 : w;
}

bool unit_quaternion(double w, double x, double y, double z) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  return std::isfinite(n) && std::abs(n - 1.0) < 0.01;
}

/// The checks a JSON pose gets (pose_message.hpp's limits), on a decoded state.
std::optional<PoseReject> check(const VehicleState& s) {
  const double values[] = {s.lat_deg, s.lon_deg, s.roll_deg, s.pitch_deg, s.yaw_deg};
  for (const double v : values) {
    if (!std::isfinite(v)) return PoseReject::not_finite;
  }
  if (s.alt_msl_m && !std::isfinite(*s.alt_msl_m)) return PoseReject::not_finite;
  if (s.velocity && !(std::isfinite(s.velocity->north_mps) && std::isfinite(s.velocity->east_mps) &&
                      std::isfinite(s.velocity->down_mps))) {
    return PoseReject::not_finite;
  }
  if (std::abs(s.lat_deg) > 90.0 || std::abs(s.lon_deg) > 180.0) return PoseReject::out_of_range;
  if (s.alt_msl_m && (*s.alt_msl_m < kMinAltM || *s.alt_msl_m > kMaxAltM)) return PoseReject::out_of_range;
  if (s.velocity && std::hypot(s.velocity->north_mps, s.velocity->east_mps, s.velocity->down_mps) > kMaxSpeedMps) {
    return PoseReject::out_of_range;
  }
  if (std::abs(s.pitch_deg) > 90.0 + 1e-9) return PoseReject::out_of_range;
  if (s.lat_deg == 0.0 && s.lon_deg == 0.0) return PoseReject::missing_key;  // no position yet
  return std::nullopt;
}

void set_euler(VehicleState& s, const Euler& e) {
  s.roll_deg = e.roll_deg;
  s.pitch_deg = e.pitch_deg;
  s.yaw_deg = e.yaw_deg;
}

Euler euler_of_radians(double roll_rad, double pitch_rad, double yaw_rad) {
  return {wrap_180_deg(roll_rad * kDegPerRad), pitch_rad * kDegPerRad, wrap_360_deg(yaw_rad * kDegPerRad)};
}

}  // namespace

Euler euler_of_quaternion(double w, double x, double y, double z) {
  const double roll = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  const double pitch = std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
  const double yaw = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return euler_of_radians(roll, pitch, yaw);
}

std::array<double, 4> quaternion_of_euler(const Euler& a) {
  const double r = a.roll_deg / kDegPerRad / 2.0, p = a.pitch_deg / kDegPerRad / 2.0, y = a.yaw_deg / kDegPerRad / 2.0;
  const double cr = std::cos(r), sr = std::sin(r), cp = std::cos(p), sp = std::sin(p), cy = std::cos(y), sy = std::sin(y);
  return {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
          cr * cp * sy - sr * sp * cy};
}

std::optional<std::uint32_t> attitude_time_boot_ms(const Frame& frame) {
  if (frame.message_id != kAttitudeId) return std::nullopt;
  return get<std::uint32_t>(frame, 0);
}

StateDecodeResult decode_state(const Frame& f) {
  VehicleState s;
  s.message_id = f.message_id;
  switch (f.message_id) {
    case kSimStateId: {
      const double q[4] = {get_f(f, 0), get_f(f, 4), get_f(f, 8), get_f(f, 12)};
      if (unit_quaternion(q[0], q[1], q[2], q[3])) {
        set_euler(s, euler_of_quaternion(q[0], q[1], q[2], q[3]));
      } else {
        set_euler(s, euler_of_radians(get_f(f, 16), get_f(f, 20), get_f(f, 24)));
      }
      const auto lat_e7 = get<std::int32_t>(f, 84), lon_e7 = get<std::int32_t>(f, 88);
      double lat = get_f(f, 52), lon = get_f(f, 56);
      // ArduPilot's SITL writes degE7 into the float fields too; without lat_int/lon_int (before
      // the extension) the pair is read as degE7 when both are beyond the degree range (one alone
      // is a nonsense value, refused as out of range: lat 400 is not 0.00004 degrees).
      if (std::abs(lat) > 90.0 && std::abs(lon) > 180.0) {
        lat *= 1e-7;
        lon *= 1e-7;
      }
      s.lat_deg = lat_e7 != 0 ? from_e7(lat_e7) : lat;
      s.lon_deg = lon_e7 != 0 ? from_e7(lon_e7) : lon;
      s.alt_msl_m = get_f(f, 60);
      s.velocity = VelocityNed{get_f(f, 72), get_f(f, 76), get_f(f, 80)};
      break;
    }
    case kHilStateQuaternionId: {
      const auto t = get<std::uint64_t>(f, 0);
      if (t != 0) s.time_usec = t;
      const double q[4] = {get_f(f, 8), get_f(f, 12), get_f(f, 16), get_f(f, 20)};
      if (!unit_quaternion(q[0], q[1], q[2], q[3])) return PoseReject::out_of_range;
      set_euler(s, euler_of_quaternion(q[0], q[1], q[2], q[3]));
      s.lat_deg = from_e7(get<std::int32_t>(f, 36));
      s.lon_deg = from_e7(get<std::int32_t>(f, 40));
      s.alt_msl_m = get<std::int32_t>(f, 44) * 1e-3;
      s.velocity = VelocityNed{get<std::int16_t>(f, 48) * 0.01, get<std::int16_t>(f, 50) * 0.01,
                               get<std::int16_t>(f, 52) * 0.01};
      break;
    }
    case kSimstateId:
      set_euler(s, euler_of_radians(get_f(f, 0), get_f(f, 4), get_f(f, 8)));
      s.lat_deg = from_e7(get<std::int32_t>(f, 36));
      s.lon_deg = from_e7(get<std::int32_t>(f, 40));
      break;
    default: return PoseReject::extra_key;  // not one of kMessages: the reader does not return those
  }
  if (const auto why = check(s)) return *why;
  return s;
}

namespace {
std::vector<std::uint8_t> encode_frame_of(std::uint32_t id, std::uint8_t crc_extra, std::span<const std::uint8_t> payload,
                                          std::size_t length, const EncodeOptions& o) {
  if (o.version == 2 && o.truncate) {
    while (length > 1 && payload[length - 1] == 0) --length;
  }
  std::vector<std::uint8_t> f;
  if (o.version == 1) {
    f = {kStartV1, static_cast<std::uint8_t>(length), o.sequence, o.system_id, o.component_id,
         static_cast<std::uint8_t>(id)};
  } else {
    f = {kStartV2, static_cast<std::uint8_t>(length), static_cast<std::uint8_t>(o.sign ? kIncompatSigned : 0), 0,
         o.sequence, o.system_id, o.component_id, static_cast<std::uint8_t>(id),
         static_cast<std::uint8_t>(id >> 8), static_cast<std::uint8_t>(id >> 16)};
  }
  f.insert(f.end(), payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(length));
  std::uint16_t crc = crc_x25(std::span<const std::uint8_t>(f.data() + 1, f.size() - 1));
  crc = crc_x25(crc_extra, crc);
  f.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  if (o.version == 2 && o.sign) f.insert(f.end(), kSignatureBytes, 0);
  return f;
}
}  // namespace

std::vector<std::uint8_t> encode_frame(std::uint32_t id, std::span<const std::uint8_t> payload,
                                       const EncodeOptions& o) {
  const MessageInfo* info = find_message(id);
  std::size_t length = payload.size();
  if (info != nullptr) length = std::min<std::size_t>(length, o.version == 1 ? info->base_length : info->full_length);
  return encode_frame_of(id, info != nullptr ? info->crc_extra : std::uint8_t{0}, payload, length, o);
}

std::vector<std::uint8_t> encode_frame(std::uint32_t id, std::uint8_t crc_extra, std::span<const std::uint8_t> payload,
                                       const EncodeOptions& o) {
  return encode_frame_of(id, crc_extra, payload, payload.size(), o);
}

std::vector<std::uint8_t> encode_state(const VehicleState& s, const EncodeOptions& options) {
  const MessageInfo* info = find_message(s.message_id);
  std::vector<std::uint8_t> p(info != nullptr ? info->full_length : 0, 0);
  const VelocityNed v = s.velocity.value_or(VelocityNed{});
  const double alt_m = s.alt_msl_m.value_or(0.0);
  const Euler e{s.roll_deg, s.pitch_deg, s.yaw_deg};
  const auto q = quaternion_of_euler(e);
  const double rad = 1.0 / kDegPerRad;
  switch (s.message_id) {
    case kSimStateId:
      for (std::size_t i = 0; i < 4; ++i) put_f(p, 4 * i, q[i]);
      put_f(p, 16, s.roll_deg * rad);
      put_f(p, 20, s.pitch_deg * rad);
      put_f(p, 24, wrap_180_deg(s.yaw_deg) * rad);
      put_f(p, 52, s.lat_deg);
      put_f(p, 56, s.lon_deg);
      put_f(p, 60, alt_m);
      put_f(p, 72, v.north_mps);
      put_f(p, 76, v.east_mps);
      put_f(p, 80, v.down_mps);
      put(p, 84, to_e7(s.lat_deg));
      put(p, 88, to_e7(s.lon_deg));
      break;
    case kHilStateQuaternionId:
      put(p, 0, s.time_usec.value_or(0));
      for (std::size_t i = 0; i < 4; ++i) put_f(p, 8 + 4 * i, q[i]);
      put(p, 36, to_e7(s.lat_deg));
      put(p, 40, to_e7(s.lon_deg));
      put(p, 44, static_cast<std::int32_t>(std::llround(alt_m * 1e3)));
      put(p, 48, static_cast<std::int16_t>(std::lround(v.north_mps * 100.0)));
      put(p, 50, static_cast<std::int16_t>(std::lround(v.east_mps * 100.0)));
      put(p, 52, static_cast<std::int16_t>(std::lround(v.down_mps * 100.0)));
      break;
    case kSimstateId:
      put_f(p, 0, s.roll_deg * rad);
      put_f(p, 4, s.pitch_deg * rad);
      put_f(p, 8, wrap_180_deg(s.yaw_deg) * rad);
      put(p, 36, to_e7(s.lat_deg));
      put(p, 40, to_e7(s.lon_deg));
      break;
    default: break;
  }
  return encode_frame(s.message_id, p, options);
}

}  // namespace gpsemu::sources::mavlink
