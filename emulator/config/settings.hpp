// What a run is configured by, grouped by where each setting applies: the process, the one epoch
// timeline every receiver shares, each receiver, and `gpsemu replay`. Values are typed and
// resolved when the configuration loads (config.hpp): specs are parsed, the cgrw one knob is
// folded into the noise configuration, fleet templates are expanded. Modules take the group they
// use, never the whole Config.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "emulator/config/spec/clock_spec.hpp"
#include "emulator/config/spec/output_spec.hpp"
#include "emulator/config/spec/pps_spec.hpp"
#include "emulator/config/spec/realtime_settings.hpp"
#include "emulator/config/spec/replay_options.hpp"
#include "emulator/config/spec/rtcm_input_spec.hpp"
#include "emulator/faults/fault.hpp"
#include "emulator/heading/moving_base.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/model/receiver_models.hpp"
#include "emulator/model/time.hpp"
#include "emulator/rtk/rtk_state.hpp"
#include "emulator/sources/sim.hpp"
#include "emulator/sources/source_spec.hpp"
#include "nmea/fix.hpp"

namespace gpsemu {

/// Settings of the whole process.
struct ProcessSettings {
  std::string log_level = "info";    ///< trace | debug | info | warn | error | off
  posix::RealtimeSettings realtime;  ///< SCHED_FIFO priority, mlockall, timer slack (realtime.hpp)
  std::optional<std::string> control_path;  ///< --control unix:PATH: the live fault socket (docs/faults.md)
  double control_idle_timeout_s = 30.0;     ///< a control client silent this long is closed (seconds; 0: never)
  std::optional<std::string> profile;       ///< --profile NAME: the receiver profile applied first (config/profiles.hpp)
  std::optional<std::string> ui;            ///< --ui [HOST:]PORT: the bench view (docs/ui.md), as given
  std::optional<std::string> ui_token;      ///< --ui-token: the token state-changing requests carry
  double status_every_s = 0.0;              ///< --status-every: a status line in the log this often (seconds; 0: never)
};

/// The one epoch timeline all receivers of a process share, and the PPS line that marks it.
struct TimelineSettings {
  double rate_hz = 1.0;               ///< epochs per second (on the UTC grid, EpochGrid)
  double latency_s = 0.05;            ///< epoch time to first byte (seconds)
  std::optional<UtcNs> start_time;    ///< first epoch; default: the next epoch after now
  std::optional<double> duration_s;   ///< stop after this much epoch time (seconds); default: until stopped
  ClockSpec clock;                    ///< realtime | scaled:K | fast (--fast) | lockstep (clock.hpp)
  std::optional<transport::PpsSpec> pps;  ///< gpio:CHIP:LINE | modem:RTS | modem:DTR; default none
  double pps_width_s = 0.1;           ///< pulse width (seconds)
  bool pps_active_low = false;        ///< line low (GPIO 0, modem line cleared) during the pulse
  std::vector<faults::Fault> faults;  ///< the scenario (--scenario, [[fault]] tables), each for one receiver or all

  /// No pacing: epochs generated as fast as possible (--fast or --clock fast).
  [[nodiscard]] bool fast() const { return clock.kind == ClockKind::fast; }
};

/// What a receiver writes (--protocol): NMEA sentences, u-blox UBX (answering the configuration
/// handshake), or both.
enum class Protocol { nmea, ubx, nmea_ubx };

/// One receiver: where its truth comes from, how it errs, what it writes and where.
struct ReceiverSettings {
  sources::SourceSpec source;                  ///< sim:NAME, replay:FILE.csv, udp:/tcp:[HOST:]PORT
  Geodetic origin{43.0725, -89.4125, 260.0};   ///< local frame origin; alt above MSL (metres)
  sources::SimOptions sim;                     ///< sim: scenario speed, heading, radius, loop
  double pose_timeout_s = 1.0;                 ///< udp:/tcp: a pose older than this is no fix (seconds)
  double pose_horizon_s = 0.2;                 ///< udp:/tcp: longest extrapolation past the newest pose (seconds)
  noise::NoiseConfig noise;                    ///< model and its parameters (cgrw axes resolved from --width)
  std::uint64_t seed = 1;                      ///< noise and sky seed (receiver i of --receivers: seed + i)
  ReceiverOptions model;                       ///< receiver model: fix quality, satellites, HDOP, cold start, outages
  nmea::FormatOptions format;                  ///< sentences, talker, NMEA version, resolution, time decimals
  bool sentences_given = false;                ///< --sentences was given (ubx: no NMEA unless it was)
  bool talker_given = false;                   ///< --talker was given (else GN for a multi-system model)
  std::optional<std::string> ephemeris;        ///< --ephemeris: RINEX navigation file of the sky
  Protocol protocol = Protocol::nmea;          ///< --protocol
  bool protocol_given = false;                 ///< --protocol was given (else a u-blox model starts in its factory state)
  std::optional<std::string> receiver_state;   ///< --receiver-state: a u-blox's BBR and flash kept across runs
  ReceiverModel receiver_model = ReceiverModel::generic;  ///< --receiver (MON-VER, configuration interface)
  std::vector<transport::OutputSpec> outputs;  ///< where NMEA goes (parsed --output specs)
  bool outputs_given = false;                  ///< --output was given (else the default; `gpsemu base` has its own)
  std::optional<std::string> tee;              ///< file copying everything sent, with send times (default none)
  std::optional<transport::RtcmInputSpec> rtcm;  ///< --rtcm: a base station's RTCM3 stream (docs/rtk.md)
  rtk::RtkTimeline rtk;                        ///< --rtk-*: the RTK state timeline (docs/rtk.md)
  heading::MovingBaseOptions moving_base;      ///< role, antenna offset (a moving-base pair: docs/heading.md)
};

/// `gpsemu replay LOG`: speed, loop, from/to, retime (replay_options.hpp).
using ReplaySettings = replay::ReplayOptions;

}  // namespace gpsemu
