// Every check that relates several options, in one place: the fleet's size, which keys a [[receiver]] table may set
// and which apply to `gpsemu replay` only (both from the options' scope), the clock against
// --fast and PPS, the pose timeouts, the cgrw axes, the time decimals against the rate, the pose
// source against the clock, and replay's options. Each throws with the message that names the
// options involved.
#pragma once

#include <string>
#include <string_view>

#include "emulator/config/settings.hpp"

namespace gpsemu {

struct Config;
struct ConfigDraft;
struct ReceiverDraft;

/// Why the option `name` cannot go in a [[receiver]] table (nullptr: it can), from its scope.
[[nodiscard]] const char* why_not_per_receiver(std::string_view name);

/// True when the option `name` applies to `gpsemu replay` only (scope replay).
[[nodiscard]] bool is_replay_only(std::string_view name);

/// The number of receivers: one per [[receiver]] table (at most kMaxReceivers), and --receivers,
/// if given, must agree with the tables of the config file `file_name`. Throws ConfigError.
void check_fleet_size(ConfigDraft& draft, const std::string& file_name);

/// Resolves --fast into the clock and checks the timeline (--fast against --clock, PPS against
/// the clock). Throws ConfigError.
void resolve_timeline(ConfigDraft& draft);

/// One receiver's settings from its draft: the cgrw one knob and explicit axes resolved into the
/// noise configuration; checks the pose timeouts, cgrw-rate and the time decimals against the
/// rate; a u-blox port is not asked for sentences a u-blox does not write (HDT, THS). Source,
/// outputs and tee are left to the caller (fleet_config.hpp). Throws ConfigError.
[[nodiscard]] ReceiverSettings resolve_receiver(const ReceiverDraft& draft, const TimelineSettings& timeline);

/// `--receiver ublox-*` without --protocol: the model as it leaves the factory (its NMEA at its
/// default baud, UBX answered on the same port), which drivers then configure. generic stays NMEA.
[[nodiscard]] bool factory_state(const ReceiverSettings& receiver);
/// Whether `receiver` has a u-blox port (UBX answered): --protocol ubx or nmea+ubx, or the factory state.
[[nodiscard]] bool has_ubx_port(const ReceiverSettings& receiver);

/// The emulator loop's checks of a receiver's pose source against the clock (a lockstep clock
/// needs a udp:/tcp: source; a socket source runs on the wall clock). Throws std::invalid_argument.
void check_source_clock(const ReceiverSettings& receiver, const TimelineSettings& timeline);

/// A subcommand (calibrate, compare, replay, ports) runs one receiver's settings: refuses a fleet.
/// Throws ConfigError.
void check_subcommand(const Config& config, const std::string& subcommand);

/// check_source_clock() for every receiver of `config` (before the emulator loop opens anything).
void check_emulator_run(const Config& config);

/// `gpsemu replay`'s checks of its options (it paces by the log: no scaled or lockstep clock;
/// --loop with --fast needs --duration). `log_has_epochs` false: the log named `log_name` is
/// refused too, in the order the checks are made. Throws std::invalid_argument.
void check_replay_settings(const TimelineSettings& timeline, const ReplaySettings& replay, bool log_has_epochs,
                           const std::string& log_name);

}  // namespace gpsemu
