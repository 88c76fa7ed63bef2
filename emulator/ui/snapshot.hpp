// One receiver's epoch as the bench view shows it and `gpsemu ctl PATH watch` prints it: a JSON
// object on one line (docs/ui.md lists its fields). Built by the loop's thread from the epoch it
// just made (pipeline/channel_set.hpp's EpochView), only while somebody watches; the HTTP server's
// threads and the control socket only pass the text on.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "emulator/model/enu.hpp"
#include "emulator/pipeline/channel_set.hpp"

namespace gpsemu::ui {

/// The reported position against the truth, in the receiver's local frame (metres).
struct EpochError {
  std::optional<Enu> truth_m;     ///< empty: no truth this epoch (a pose source that went quiet)
  std::optional<Enu> reported_m;  ///< empty: no fix
  [[nodiscard]] std::optional<Enu> error_m() const;
  [[nodiscard]] std::optional<double> horizontal_m() const;
  [[nodiscard]] std::optional<double> vertical_m() const;
};
/// The error of `view`'s fix against its channel's truth.
[[nodiscard]] EpochError epoch_error(const EpochView& view);

/// What the epoch does not say itself.
struct SnapshotContext {
  std::size_t receivers = 1;
  std::uint64_t epoch = 0;          ///< this receiver's epochs so far
  double bytes_per_s = 0.0;         ///< what its outputs took lately (bytes a second)
  std::uint64_t late_epochs = 0;    ///< skipped late, the whole run
  std::size_t page_clients = 0;     ///< browsers watching
  std::size_t watch_clients = 0;    ///< `gpsemu ctl PATH watch` clients
};

/// The epoch as one line of JSON ({"class":"EPOCH",...}, no '\n').
[[nodiscard]] std::string epoch_json(const EpochView& view, const EpochError& error, const SnapshotContext& context);

/// "GPS", "GLONASS", ... (the sky plot's legend).
[[nodiscard]] const char* system_name(nmea::GnssSystem system);
/// "none", "gps", "dgps", "rtk-float", "rtk-fixed", ...
[[nodiscard]] const char* quality_name(nmea::FixQuality quality);

}  // namespace gpsemu::ui
