// gpsemu as a library: the receiver model (truth + noise -> the fix and the NMEA bytes a receiver
// would report) and the noise models, configured with the same keys as the command line and the
// TOML config file (`gpsemu --help`). Only standard types cross this header: it is what an
// installed package exposes (find_package(gpsemu) -> gpsemu::gpsemu), and what the Python module
// wraps. The same keys, seed and start time give the CLI's bytes exactly.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace gpsemu::api {

/// Options by key: the CLI's long flag names without dashes (the config file's keys), each with
/// its values as text, e.g. {{"noise", {"cgrw"}}, {"width", {"1.0"}}, {"seed", {"7"}}}. A flag
/// takes "true" or "false"; a repeatable option ("outage") takes several values.
using Options = std::vector<std::pair<std::string, std::vector<std::string>>>;

/// A local East/North/Up vector about the configured origin (metres, or metres per second).
using Enu = std::array<double, 3>;

/// A WGS84 position: latitude (degrees), longitude (degrees), altitude above MSL (metres).
using LatLonAlt = std::array<double, 3>;

/// One epoch of receiver output.
struct Epoch {
  std::int64_t time_ns = 0;  ///< epoch time, UTC nanoseconds since 1970-01-01T00:00:00Z
  bool has_fix = false;      ///< false: no position (outage, cold start, no truth); fields below NaN
  LatLonAlt position{};      ///< reported position (truth + noise), degrees, degrees, metres MSL
  Enu position_enu_m{};      ///< the same in the local frame about the origin (metres)
  double speed_mps = 0.0;    ///< reported speed over ground (metres per second)
  double vel_up_mps = 0.0;   ///< reported vertical velocity, up positive (metres per second)
  int satellites_used = 0;
  double hdop = 0.0;
  std::string nmea;          ///< the epoch's sentences, exactly the bytes the CLI writes
};

/// Thrown for a bad key or value (the message names the key) and for a bad call.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A noise model alone: the error a receiver adds, in local ENU metres, as a function of time.
class NoiseGenerator {
 public:
  /// Uses the keys noise, width, cgrw-*, chrono, gaussian-*, gm-*, seed (others are accepted and
  /// ignored). `config_file`: a TOML file read first, as with --config. Throws Error.
  explicit NoiseGenerator(const Options& options, const std::optional<std::string>& config_file = {});
  ~NoiseGenerator();
  NoiseGenerator(NoiseGenerator&&) noexcept;
  NoiseGenerator& operator=(NoiseGenerator&&) noexcept;

  /// The error at `since_start_ns` after the first epoch; query with non-decreasing times.
  [[nodiscard]] Enu at(std::int64_t since_start_ns);
  /// The next `n` samples at `rate_hz` (the first at the time after the last sample generated, or
  /// 0 for a new generator), written to `out_enu_m` as n rows of east, north, up. Throws Error.
  void generate(std::size_t n, double rate_hz, double* out_enu_m);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The receiver: feed it the truth at each epoch, get the fix and the NMEA bytes.
class Receiver {
 public:
  /// Every key of the CLI (rate, origin, noise, seed, start-time, sentences, fix-quality, ...);
  /// start-time defaults to the next epoch after now, as on the CLI. The pose source key
  /// (source, default sim:stationary) is used only by step(). Outputs and PPS are ignored.
  /// Throws Error.
  explicit Receiver(const Options& options, const std::optional<std::string>& config_file = {});
  ~Receiver();
  Receiver(Receiver&&) noexcept;
  Receiver& operator=(Receiver&&) noexcept;

  /// The next epoch with the truth from the configured simulator source (sim:stationary,
  /// sim:line, sim:circle, sim:waypoints:FILE): the CLI's `--fast` output, epoch by epoch.
  [[nodiscard]] Epoch step();
  /// The next epoch with the truth given in the local frame (metres, metres per second).
  [[nodiscard]] Epoch step_enu(const Enu& position_m, const Enu& velocity_mps = {});
  /// The next epoch with the truth given as a WGS84 position (altitude above MSL) and an ENU velocity.
  [[nodiscard]] Epoch step_geodetic(const LatLonAlt& position, const Enu& velocity_mps = {});
  /// The next epoch without truth (the simulator has no pose): no fix.
  [[nodiscard]] Epoch step_no_fix();

  /// The control socket's requests (docs/faults.md) on this receiver's faults, in-process: one JSON
  /// object in ({"fault":"jam","db":25,"ramp_s":5}, {"clear":"jam"}, {"status":true}), the JSON
  /// answer out ({"class":"FAULT",...}, or {"class":"ERROR","message":...}). A fault applies from
  /// the next step. Never throws for a bad request (the answer says what was wrong).
  [[nodiscard]] std::string control(const std::string& request);

  [[nodiscard]] std::int64_t next_epoch_ns() const;  ///< time of the epoch the next step reports
  [[nodiscard]] double rate_hz() const;              ///< epochs per second
  [[nodiscard]] LatLonAlt origin() const;            ///< the local frame's origin
  [[nodiscard]] Enu to_enu(const LatLonAlt& position) const;
  [[nodiscard]] LatLonAlt to_geodetic(const Enu& position_m) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One configuration key (the CLI's long flag and the config file's key).
struct OptionInfo {
  std::string name;        ///< "rate", "origin", ...
  std::string value_name;  ///< "HZ", "LAT,LON,ALT"; empty for a flag ("true"/"false")
  std::string help;        ///< with unit and default
  bool repeatable = false; ///< takes several values ("outage", "output")
};
/// Every key the constructors accept.
[[nodiscard]] std::vector<OptionInfo> option_info();

/// One request to a running gpsemu's control socket (--control): `socket` is unix:PATH, a PATH, or
/// tcp:HOST:PORT; returns the answer line (JSON). Throws Error when it cannot connect or no answer
/// comes within `timeout_s`.
[[nodiscard]] std::string control_request(const std::string& socket, const std::string& request, double timeout_s = 5.0);

/// The library's version, "0.1.0".
[[nodiscard]] std::string version();

}  // namespace gpsemu::api
