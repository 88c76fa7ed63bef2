#include "emulator/model/geo_near.hpp"

#include <cmath>
#include <numbers>

namespace gpsemu {
namespace {

constexpr double kA = 6378137.0;              // WGS84 semi-major axis (m)
constexpr double kF = 1.0 / 298.257223563;    // WGS84 flattening
constexpr double kE2 = kF * (2.0 - kF);       // first eccentricity squared
constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kMaxLatDeg = 89.0;           // nearer a pole the linearisation is not used

/// ECEF of a geodetic point from its latitude's and longitude's sine and cosine (metres).
void ecef_of(double sp, double cp, double sl, double cl, double h, double out[3]) {
  const double n = kA / std::sqrt(1.0 - kE2 * sp * sp);
  out[0] = (n + h) * cp * cl;
  out[1] = (n + h) * cp * sl;
  out[2] = (n * (1.0 - kE2) + h) * sp;
}

/// sin and cos of a + d from a's and the small angle d (radians; |d| < 1e-5: the series' next
/// terms are below 1e-26).
void sincos_near(double sa, double ca, double d, double& s, double& c) {
  const double sd = d * (1.0 - d * d / 6.0), cd = 1.0 - d * d / 2.0;
  s = sa * cd + ca * sd;
  c = ca * cd - sa * sd;
}

}  // namespace

Enu NearGeodetic::near_to_enu(const Geodetic& g) const {
  double sp, cp, sl, cl;
  sincos_near(ref_sin_lat_, ref_cos_lat_, (g.lat_deg - ref_.lat_deg) / kDegPerRad, sp, cp);
  sincos_near(ref_sin_lon_, ref_cos_lon_, (g.lon_deg - ref_.lon_deg) / kDegPerRad, sl, cl);
  double x[3];
  ecef_of(sp, cp, sl, cl, g.alt_m, x);
  const double d[3] = {x[0] - origin_ecef_m_[0], x[1] - origin_ecef_m_[1], x[2] - origin_ecef_m_[2]};
  const auto& o = origin_axes_;
  return {o[0][0] * d[0] + o[0][1] * d[1] + o[0][2] * d[2] + bias_m_.east_m,
          o[1][0] * d[0] + o[1][1] * d[1] + o[1][2] * d[2] + bias_m_.north_m,
          o[2][0] * d[0] + o[2][1] * d[1] + o[2][2] * d[2] + bias_m_.up_m};
}

void NearGeodetic::set_reference(const LocalFrame& frame, const Enu& point, const Geodetic& g) {
  valid_ = std::abs(g.lat_deg) < kMaxLatDeg;
  if (!valid_) return;
  ref_enu_ = point;
  ref_ = g;
  // The point's own east/north/up axes expressed in the frame's: the frame's unit vectors turned
  // by the difference in longitude and latitude (both frames on the same ellipsoid).
  const double lat = g.lat_deg / kDegPerRad, lon = g.lon_deg / kDegPerRad;
  const double lat0 = frame.origin().lat_deg / kDegPerRad, lon0 = frame.origin().lon_deg / kDegPerRad;
  const double sp = std::sin(lat), cp = std::cos(lat), sl = std::sin(lon), cl = std::cos(lon);
  const double sp0 = std::sin(lat0), cp0 = std::cos(lat0), sl0 = std::sin(lon0), cl0 = std::cos(lon0);
  // ECEF unit vectors: rows east, north, up.
  const double p[3][3] = {{-sl, cl, 0.0}, {-sp * cl, -sp * sl, cp}, {cp * cl, cp * sl, sp}};
  const double o[3][3] = {{-sl0, cl0, 0.0}, {-sp0 * cl0, -sp0 * sl0, cp0}, {cp0 * cl0, cp0 * sl0, sp0}};
  // r[i][j]: component i of the point's axes per metre along the frame's axis j.
  double r[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r[i][j] = p[i][0] * o[j][0] + p[i][1] * o[j][1] + p[i][2] * o[j][2];
  }
  const double w = std::sqrt(1.0 - kE2 * sp * sp);
  const double meridian_m = kA * (1.0 - kE2) / (w * w * w) + g.alt_m;
  const double prime_m = (kA / w + g.alt_m) * cp;
  ref_sin_lat_ = sp;
  ref_cos_lat_ = cp;
  ref_sin_lon_ = sl;
  ref_cos_lon_ = cl;
  ecef_of(sp0, cp0, sl0, cl0, frame.origin().alt_m, origin_ecef_m_);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) origin_axes_[i][j] = o[i][j];
  }
  bias_m_ = {};
  const Enu at = near_to_enu(g);
  bias_m_ = {point.east_m - at.east_m, point.north_m - at.north_m, point.up_m - at.up_m};
  for (int j = 0; j < 3; ++j) {
    jacobian_[0][j] = r[1][j] / meridian_m * kDegPerRad;
    jacobian_[1][j] = r[0][j] / prime_m * kDegPerRad;
    jacobian_[2][j] = r[2][j];
  }
}

Geodetic NearGeodetic::to_geodetic(const LocalFrame& frame, const Enu& point) {
  const double d[3] = {point.east_m - ref_enu_.east_m, point.north_m - ref_enu_.north_m, point.up_m - ref_enu_.up_m};
  if (!valid_ || !(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= kNearRadiusM * kNearRadiusM)) {
    const Geodetic exact = frame.to_geodetic(point);
    set_reference(frame, point, exact);
    return exact;
  }
  Geodetic g{ref_.lat_deg + jacobian_[0][0] * d[0] + jacobian_[0][1] * d[1] + jacobian_[0][2] * d[2],
             ref_.lon_deg + jacobian_[1][0] * d[0] + jacobian_[1][1] * d[1] + jacobian_[1][2] * d[2],
             ref_.alt_m + jacobian_[2][0] * d[0] + jacobian_[2][1] * d[1] + jacobian_[2][2] * d[2]};
  // Newton: what is left of the linearisation's error, measured with the forward conversion.
  const Enu at = near_to_enu(g);
  const double e[3] = {point.east_m - at.east_m, point.north_m - at.north_m, point.up_m - at.up_m};
  g.lat_deg += jacobian_[0][0] * e[0] + jacobian_[0][1] * e[1] + jacobian_[0][2] * e[2];
  g.lon_deg += jacobian_[1][0] * e[0] + jacobian_[1][1] * e[1] + jacobian_[1][2] * e[2];
  g.alt_m += jacobian_[2][0] * e[0] + jacobian_[2][1] * e[1] + jacobian_[2][2] * e[2];
  g.lon_deg = wrap_lon_deg(g.lon_deg);
  return g;
}

}  // namespace gpsemu
