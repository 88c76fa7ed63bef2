#include "emulator/sources/pose_message.hpp"

#include <cctype>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

namespace gpsemu::sources {
namespace {

enum Key : int { k_t, k_lat, k_lon, k_alt, k_x, k_y, k_z, k_ve, k_vn, k_vu, k_yaw, k_pitch, k_roll, k_count };
constexpr std::array<std::string_view, k_count> kKeyNames{"t",  "lat", "lon", "alt",     "x",        "y",       "z",
                                                          "ve", "vn",  "vu",  "yaw_deg", "pitch_deg", "roll_deg"};
/// Largest |yaw_deg| accepted (degrees): one turn either way.
constexpr double kMaxYawDeg = 360.0;

constexpr unsigned bit(Key k) { return 1u << k; }

/// Streams the JSON once (no document is built) and accepts only a flat object of known keys
/// with number values. Stops at the first problem and remembers why.
class FlatNumberObject final : public nlohmann::json_sax<nlohmann::json> {
 public:
  std::array<double, k_count> value{};
  unsigned seen = 0;
  std::optional<PoseReject> reject;  ///< a semantic problem (syntax errors go to syntax_error)
  bool syntax_error = false;

  bool null() override { return not_number(); }
  bool boolean(bool) override { return not_number(); }
  bool number_integer(number_integer_t v) override { return number(static_cast<double>(v)); }
  bool number_unsigned(number_unsigned_t v) override { return number(static_cast<double>(v)); }
  bool number_float(number_float_t v, const string_t&) override { return number(v); }
  bool string(string_t&) override { return not_number(); }
  bool binary(binary_t&) override { return not_number(); }
  bool start_object(std::size_t) override {
    if (depth_++ == 0) return true;
    return not_number();  // a nested object as a value
  }
  bool end_object() override {
    --depth_;
    return true;
  }
  bool start_array(std::size_t) override { return not_number(); }
  bool end_array() override { return true; }
  bool key(string_t& name) override {
    for (int k = 0; k < k_count; ++k) {
      if (name == kKeyNames[static_cast<std::size_t>(k)]) {
        if (seen & (1u << k)) return fail(PoseReject::extra_key);  // a repeated key
        current_ = k;
        return true;
      }
    }
    return fail(PoseReject::extra_key);
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    if (e.id == 406) return fail(PoseReject::not_finite);  // "number overflow": beyond double range
    syntax_error = true;
    return false;
  }

 private:
  bool fail(PoseReject r) {
    reject = r;
    return false;
  }
  bool not_number() { return fail(depth_ == 0 ? PoseReject::not_object : PoseReject::not_a_number); }
  bool number(double v) {
    if (depth_ == 0) return fail(PoseReject::not_object);
    if (!std::isfinite(v)) return fail(PoseReject::not_finite);
    value[static_cast<std::size_t>(current_)] = v;
    seen |= 1u << current_;
    return true;
  }
  int depth_ = 0;
  int current_ = 0;
};

/// NaN, Infinity (Python's json.dumps), nan, inf (C's printf) as a whole word.
bool contains_non_finite_literal(std::string_view s) {
  const auto is_word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; };
  for (const std::string_view word : {"NaN", "Infinity", "nan", "inf"}) {
    for (auto at = s.find(word); at != std::string_view::npos; at = s.find(word, at + 1)) {
      const bool starts = at == 0 || !is_word(s[at - 1]);
      const bool ends = at + word.size() == s.size() || !is_word(s[at + word.size()]);
      if (starts && ends) return true;
    }
  }
  return false;
}

PoseDecodeResult decode(std::string_view bytes) {
  if (bytes.size() > kMaxPoseMessageBytes) return PoseReject::too_large;
  FlatNumberObject h;
  const bool ok = nlohmann::json::sax_parse(bytes.begin(), bytes.end(), &h);
  if (h.reject) return *h.reject;
  if (!ok || h.syntax_error) {
    // JSON has no NaN or infinity; senders that write them (Python's json.dumps does) are told so.
    return contains_non_finite_literal(bytes) ? PoseReject::not_finite : PoseReject::not_json;
  }
  const unsigned seen = h.seen;
  const auto& v = h.value;
  const auto has = [seen](Key k) { return (seen & bit(k)) != 0; };
  const bool geodetic = seen & (bit(k_lat) | bit(k_lon) | bit(k_alt));
  const bool local = seen & (bit(k_x) | bit(k_y) | bit(k_z));
  if (geodetic && local) return PoseReject::mixed_position;
  if (!geodetic && !local) return PoseReject::missing_key;
  if (geodetic && !(has(k_lat) && has(k_lon))) return PoseReject::missing_key;
  if (local && !(has(k_x) && has(k_y))) return PoseReject::missing_key;
  if (has(k_ve) != has(k_vn) || (has(k_vu) && !has(k_ve))) return PoseReject::missing_key;

  PoseMessage m;
  if (has(k_t)) {
    if (std::abs(v[k_t]) > kMaxSenderTimeS) return PoseReject::out_of_range;
    m.sender_time_s = v[k_t];
  }
  if (geodetic) {
    if (std::abs(v[k_lat]) > 90.0 || std::abs(v[k_lon]) > 180.0) return PoseReject::out_of_range;
    GeodeticPose g{v[k_lat], v[k_lon], std::nullopt};
    if (has(k_alt)) {
      if (v[k_alt] < kMinAltM || v[k_alt] > kMaxAltM) return PoseReject::out_of_range;
      g.alt_msl_m = v[k_alt];
    }
    m.position = g;
  } else {
    const Enu p{v[k_x], v[k_y], has(k_z) ? v[k_z] : 0.0};
    if (std::abs(p.east_m) > kMaxLocalCoordinateM || std::abs(p.north_m) > kMaxLocalCoordinateM ||
        std::abs(p.up_m) > kMaxLocalCoordinateM) {
      return PoseReject::out_of_range;
    }
    m.position = p;
  }
  if (has(k_ve)) {
    const Enu vel{v[k_ve], v[k_vn], has(k_vu) ? v[k_vu] : 0.0};
    if (std::abs(vel.east_m) > kMaxSpeedMps || std::abs(vel.north_m) > kMaxSpeedMps ||
        std::abs(vel.up_m) > kMaxSpeedMps) {
      return PoseReject::out_of_range;
    }
    m.velocity_mps = vel;
  }
  if (has(k_yaw)) {
    if (std::abs(v[k_yaw]) > kMaxYawDeg) return PoseReject::out_of_range;
    m.yaw_deg = wrap_360_deg(v[k_yaw]);
  }
  if (has(k_pitch)) {
    if (std::abs(v[k_pitch]) > 90.0) return PoseReject::out_of_range;
    m.pitch_deg = v[k_pitch];
  }
  if (has(k_roll)) {
    if (std::abs(v[k_roll]) > 180.0) return PoseReject::out_of_range;
    m.roll_deg = v[k_roll];
  }
  return m;
}

}  // namespace

double wrap_360_deg(double deg) {
  const double wrapped = deg - 360.0 * std::floor(deg / 360.0);
  return wrapped >= 360.0 ? 0.0 : wrapped;  // -1e-17 + 360 rounds to 360
}

std::optional<double> interpolate_yaw_deg(const std::optional<double>& a, const std::optional<double>& b,
                                          double f) {
  if (!a || !b) return a;
  double d = *b - *a;
  d -= 360.0 * std::round(d / 360.0);
  return wrap_360_deg(*a + f * d);
}

const char* to_string(PoseReject reason) {
  switch (reason) {
    case PoseReject::too_large: return "too_large";
    case PoseReject::partial_line: return "partial_line";
    case PoseReject::not_json: return "not_json";
    case PoseReject::not_object: return "not_object";
    case PoseReject::missing_key: return "missing_key";
    case PoseReject::extra_key: return "extra_key";
    case PoseReject::mixed_position: return "mixed_position";
    case PoseReject::not_a_number: return "not_a_number";
    case PoseReject::not_finite: return "not_finite";
    case PoseReject::out_of_range: return "out_of_range";
    case PoseReject::out_of_order: return "out_of_order";
    case PoseReject::too_fast: return "too_fast";
    case PoseReject::flood: return "flood";
    case PoseReject::other_sender: return "other_sender";
    case PoseReject::too_many_clients: return "too_many_clients";
    case PoseReject::kernel_overflow: return "kernel_overflow";
  }
  return "unknown";
}

PoseDecodeResult decode_pose(std::string_view bytes) noexcept {
  try {
    return decode(bytes);
  } catch (...) {  // only std::bad_alloc can get here: refuse the message, keep running
    return PoseReject::not_json;
  }
}

}  // namespace gpsemu::sources
