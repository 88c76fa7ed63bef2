// ENU -> WGS84 geodetic for points near one another (the receiver's noisy positions about its
// truth): a linearisation about a reference point converted exactly (LocalFrame::to_geodetic),
// then one Newton step through the forward conversion (geodetic -> ECEF -> the frame's ENU, with
// the sine and cosine of the guess from the reference's by the angle-sum formulas). Within
// kNearRadiusM of the reference the result differs from to_geodetic's by below 1e-10 m (the
// Newton step leaves (d^2/R) x (d/R) of the linearisation's d^2/2R); farther away, or near a pole,
// the point is converted exactly and becomes the new reference. The result is the exact
// conversion's to its last bits' rounding (ECEF coordinates of 6.4e6 m carry ~1e-9 m): it may
// differ in the last printed digit at the finest resolutions (docs/performance.md).
#pragma once

#include "emulator/model/enu.hpp"
#include "emulator/model/geo.hpp"

namespace gpsemu {

class NearGeodetic {
 public:
  /// Distance from the reference within which the linearisation is used (metres).
  static constexpr double kNearRadiusM = 10.0;

  /// Converts `point` (ENU metres in `frame`) as frame.to_geodetic does. Uses and updates the
  /// reference; `frame` must be the same on every call.
  [[nodiscard]] Geodetic to_geodetic(const LocalFrame& frame, const Enu& point);

 private:
  void set_reference(const LocalFrame& frame, const Enu& point, const Geodetic& g);

  bool valid_ = false;
  /// The frame's ENU of a geodetic point near the reference (angles within a few arc seconds).
  [[nodiscard]] Enu near_to_enu(const Geodetic& g) const;

  Enu ref_enu_;
  Geodetic ref_;
  double ref_sin_lat_ = 0.0, ref_cos_lat_ = 1.0, ref_sin_lon_ = 0.0, ref_cos_lon_ = 1.0;
  double origin_ecef_m_[3] = {};
  double origin_axes_[3][3] = {};  // rows: the frame's east, north, up unit vectors in ECEF
  Enu bias_m_;  // the exact conversion's ENU of the reference minus near_to_enu's (rounding)
  // d(lat, lon, h) / d(east, north, up) of the frame at the reference (degrees or metres per metre).
  double jacobian_[3][3] = {};
};

}  // namespace gpsemu
