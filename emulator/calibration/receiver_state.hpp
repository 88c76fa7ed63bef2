// What a stationary receiver's log says about its own state, beside its noise (docs/
// noise-and-calibration.md "The receiver's state"): satellites used and HDOP (GGA), PDOP and the
// satellites used (GSA), C/N0 and elevations (GSV); from these the lowest elevation it used (its
// elevation mask, at most) and, with the noise's horizontal sigma, its UERE = sigma_h / median
// HDOP. Written as config keys (uere, elevation-mask, satellites) and shown by calibrate, compare
// and judge. Reads the log's bytes itself (any talker, binary and junk skipped). Pure.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

namespace gpsemu::calibration {

/// Median and the 10th/90th percentiles of a logged quantity.
struct Spread {
  double median = 0.0, p10 = 0.0, p90 = 0.0;
  std::size_t count = 0;
};

struct ReceiverState {
  std::optional<Spread> satellites_used;  ///< GGA field 7, epochs with a fix
  std::optional<Spread> hdop;             ///< GGA field 8, epochs with a fix
  std::optional<Spread> pdop;             ///< GSA field 15 (the first GSA of an epoch)
  std::optional<Spread> cn0_dbhz;         ///< every GSV C/N0 of a tracked satellite
  /// The lowest elevation (degrees) of a satellite listed as used in GSA, read from GSV; the
  /// receiver's elevation mask is at most this.
  std::optional<double> lowest_used_elevation_deg;
  std::optional<double> uere_m;           ///< sigma_h / median HDOP (set by with_sigmas)
  /// The GGA fix quality most epochs with a fix have (1 gps, 2 dgps, 4 rtk-fixed, 5 rtk-float; others
  /// are not a quality the emulator reports and are left out): the quality the noise was measured at.
  std::optional<int> fix_quality;
  /// hypot of GST's latitude and longitude sigmas (fields 6 and 7), epochs with both: what the
  /// receiver claims its horizontal accuracy is.
  std::optional<Spread> gst_sigma_h_m;
  /// What the receiver claims over what the calibrated model's error is (set by with_sigmas),
  /// 0.01..10: median GST sigma_h, or without GST the log's own sigma_h (a receiver's estimate comes
  /// from its residuals and does not see the slow wander a model extrapolates beyond the log), over
  /// the model's long-run sigma_h (estimate_noise_sigma_m, what the emulator's accuracy starts from).
  std::optional<double> accuracy_ratio;
  std::optional<double> model_sigma_h_m;  ///< the calibrated model's long-run sigma_h (with_sigmas)
};

[[nodiscard]] ReceiverState learn_receiver_state(std::string_view log_bytes);
/// The same, read from `log` 1 MiB at a time: memory follows the epochs, not the log's bytes (a
/// 50 MB log read whole took 14x its size at the end of calibrate).
[[nodiscard]] ReceiverState learn_receiver_state(std::istream& log);

/// Sets `uere_m` from the log's horizontal position sigma (hypot of the east and north standard
/// deviations, metres) and its median HDOP, and `accuracy_ratio` from the log's GST (or that sigma)
/// and the calibrated model's long-run horizontal sigma `model_sigma_h_m` (0: not set).
[[nodiscard]] ReceiverState with_sigmas(ReceiverState state, double sigma_h_m, double model_sigma_h_m);

/// Comment lines and the keys uere, elevation-mask, satellites, fix-quality with noise-quality (a
/// log not at quality 1) and accuracy-ratio (those the log gives), for the calibrated config file.
[[nodiscard]] std::string receiver_state_toml(const ReceiverState& state);

/// A few lines for a person: satellites, DOPs, C/N0, mask, UERE.
[[nodiscard]] std::string receiver_state_summary(const ReceiverState& state);

/// Whether a receiver's state passes the GPS checks of PX4's EKF2 with its defaults (satellites
/// >= EKF2_REQ_NSATS 6, PDOP <= EKF2_REQ_PDOP 2.5, horizontal accuracy <= EKF2_REQ_EPH 3 m) and
/// ArduPilot's HDOP arming check (HDOP <= 2.5, GPS_HDOP_GOOD 250).
struct GateCheck {
  int satellites = 0;
  double hdop = 0.0, pdop = 0.0, eph_m = 0.0;
  [[nodiscard]] bool px4_ok() const { return satellites >= 6 && pdop <= 2.5 && eph_m <= 3.0; }
  [[nodiscard]] bool ardupilot_ok() const { return hdop <= 2.5; }
};

}  // namespace gpsemu::calibration
