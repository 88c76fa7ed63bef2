// The receiver table: every receiver model gpsemu can be (--receiver) and its facts below any
// protocol, one row each (receiver_models.cpp): what it tracks, how fast it solves, what RTCM3
// corrections give it, whether it can be a moving base, its clock, its default baud rate and its
// firmware. The protocols read what they need from here; each keeps only its own identity strings
// beside it (u-blox: MON-VER and its configuration interface, in the u-blox folder). Adding a
// model: docs/development.md, "Adding a receiver model". Pure values (gpsemu_facts).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "emulator/model/sky/tracking.hpp"
#include "nmea/sentence_set.hpp"

namespace gpsemu {

/// How many rows the table has.
inline constexpr std::size_t kReceiverModels = 5;

/// The models, in the table's order (generic answers as an M8N, solving as fast as any u-blox: 40 Hz).
enum class ReceiverModel { generic, ublox_m8n, ublox_m9n, ublox_f9p, ublox_m10 };

/// What RTCM3 corrections on its input give a model.
enum class Corrections {
  none,   ///< ignored (M10, SPG 5.10)
  dgnss,  ///< code-phase DGNSS only, never RTK float/fixed (M9N: SPG firmware)
  rtk,    ///< RTK float and fixed (F9P: HPG firmware)
};

/// The local oscillator: a TCXO whose frequency offset (the drift) wanders as a first-order
/// Gauss-Markov process around a per-unit offset (model/receiver_clock.hpp).
struct ClockQuality {
  double unit_offset_sigma_ns_per_s = 200.0;  ///< offset between units (ns/s: 200 is 0.2 ppm)
  double unit_offset_max_ns_per_s = 500.0;    ///< clamped at (ns/s)
  double drift_wander_sigma_ns_per_s = 5.0;   ///< stationary wander around the offset (ns/s)
  double drift_tau_s = 300.0;                 ///< its correlation time (temperature; seconds)
};

struct ReceiverFacts {
  std::string_view name;      ///< the --receiver value: "ublox-f9p"
  std::string_view vendor;    ///< "u-blox"
  std::string_view module;    ///< the module it answers as: "ZED-F9P"
  std::string_view firmware;  ///< "HPG 1.32"
  sky::Tracking tracking;     ///< systems, signals, channels, mask, C/N0 threshold, UERE
  /// The shortest time between navigation solutions with its systems as shipped.
  std::chrono::milliseconds fastest_solution_period{100};
  Corrections corrections = Corrections::rtk;
  bool moving_base = false;  ///< can send and take the moving-base corrections of dual-antenna heading
  ClockQuality clock;
  std::uint32_t default_baud = 9600;  ///< its UART after a factory reset (bits per second)
  nmea::SentenceSet nmea_default;     ///< the NMEA sentences it writes after a factory reset
  nmea::SentenceSet nmea_written;     ///< every NMEA sentence it can be set to write (u-blox: no HDT, THS)
};

/// Every row, in ReceiverModel's order.
[[nodiscard]] std::span<const ReceiverFacts> receiver_table();
[[nodiscard]] const ReceiverFacts& facts_of(ReceiverModel model);
/// The model named `name` ("ublox-f9p"), nullopt for an unknown name.
[[nodiscard]] std::optional<ReceiverModel> receiver_model_from_name(std::string_view name);
/// Every model's name in table order, comma-separated ("generic, ublox-m8n, ..."): for messages.
[[nodiscard]] std::string receiver_model_names();

}  // namespace gpsemu
