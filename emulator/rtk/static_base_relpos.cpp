// NAV-RELPOSNED of a rover with a fixed base (see static_base_relpos.hpp).
#include "emulator/rtk/static_base_relpos.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <GeographicLib/Geocentric.hpp>


namespace gpsemu::rtk {

NedOffset ned_from(const BasePosition& from, double to_x_m, double to_y_m, double to_z_m) {
  double lat_deg = 0.0, lon_deg = 0.0, h_m = 0.0;
  GeographicLib::Geocentric::WGS84().Reverse(from.ecef_x_m, from.ecef_y_m, from.ecef_z_m, lat_deg, lon_deg, h_m);
  const double phi = lat_deg * std::numbers::pi / 180.0, lambda = lon_deg * std::numbers::pi / 180.0;
  const double dx = to_x_m - from.ecef_x_m, dy = to_y_m - from.ecef_y_m, dz = to_z_m - from.ecef_z_m;
  const double east = -std::sin(lambda) * dx + std::cos(lambda) * dy;
  const double north =
      -std::sin(phi) * std::cos(lambda) * dx - std::sin(phi) * std::sin(lambda) * dy + std::cos(phi) * dz;
  const double up = std::cos(phi) * std::cos(lambda) * dx + std::cos(phi) * std::sin(lambda) * dy + std::sin(phi) * dz;
  return {north, east, -up};
}

RelativePosition static_base_relpos(const RtkStatus& status, const std::optional<BasePosition>& base,
                                  const nmea::Fix& fix) {
  RelativePosition rel;
  if (!fix.has_fix()) return rel;
  if (status.station_id) {
    rel.ref_station_id = *status.station_id;
  } else if (base) {
    rel.ref_station_id = base->station_id;
  }
  rel.diff_soln = status.differential();
  rel.carrier = status.quality == nmea::FixQuality::rtk_fixed   ? CarrierSolution::fixed
                : status.quality == nmea::FixQuality::rtk_float ? CarrierSolution::floating
                                                                : CarrierSolution::none;
  if (!rel.diff_soln || !base) return rel;
  double x = 0.0, y = 0.0, z = 0.0;
  GeographicLib::Geocentric::WGS84().Forward(fix.lat_deg, fix.lon_deg, fix.alt_msl_m + fix.geoid_sep_m, x, y, z);
  const NedOffset d = ned_from(*base, x, y, z);
  rel.north_m = d.north_m;
  rel.east_m = d.east_m;
  rel.down_m = d.down_m;
  rel.length_m = std::sqrt(d.north_m * d.north_m + d.east_m * d.east_m + d.down_m * d.down_m);
  // The epoch's accuracy (floored once by the model): hypot(accN, accE) is NAV-PVT's hAcc, accD its vAcc.
  const struct {
    double north_m, east_m, down_m;
  } acc{fix.sigma_lat_m, fix.sigma_lon_m, fix.sigma_alt_m};
  rel.acc_north_m = acc.north_m;
  rel.acc_east_m = acc.east_m;
  rel.acc_down_m = acc.down_m;
  if (rel.length_m > 0.0) {
    const double n = d.north_m / rel.length_m, e = d.east_m / rel.length_m, v = d.down_m / rel.length_m;
    rel.acc_length_m = std::sqrt(n * n * acc.north_m * acc.north_m + e * e * acc.east_m * acc.east_m +
                                 v * v * acc.down_m * acc.down_m);
  } else {
    rel.acc_length_m = std::max({acc.north_m, acc.east_m, acc.down_m});
  }
  rel.rel_pos_valid = true;
  return rel;
}

}  // namespace gpsemu::rtk
