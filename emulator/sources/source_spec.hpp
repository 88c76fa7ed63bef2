// The pose source a user names (`--source sim:line`, `udp:5600`, `replay:drive.csv`), parsed once
// when the configuration loads into a value that make_source() switches on.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "transport/input/pose_socket.hpp"

namespace gpsemu::sources {

enum class SourceKind {
  sim,     ///< `sim:NAME[:FILE]`: a built-in scenario (sim.hpp)
  replay,  ///< `replay:FILE.csv`: a recorded truth trajectory (trajectory_source.hpp)
  udp,     ///< `udp:[HOST:]PORT`: JSON poses in datagrams from a simulator
  tcp,     ///< `tcp:[HOST:]PORT`: JSON poses, one a line, from simulators that connect
  mavlink_udp,  ///< `mavlink:udp:[HOST:]PORT`: MAVLink datagrams (SIM_STATE ...) from a simulator
  mavlink_tcp,  ///< `mavlink:tcp:HOST:PORT`: a MAVLink stream gpsemu connects to (ArduPilot SITL's 5760)
};

struct SourceSpec {
  SourceKind kind = SourceKind::sim;
  /// sim: the scenario as make_sim_source() takes it ("stationary", "line", "circle", "waypoints:FILE").
  std::string scenario = "stationary";
  std::filesystem::path path;         ///< replay: the trajectory CSV file
  transport::PoseEndpoint endpoint;   ///< udp, tcp, mavlink_udp: where to listen; mavlink_tcp: where to connect
  std::string text = "sim:stationary";  ///< the spec as written (for messages)

  /// JSON poses over a socket (udp:, tcp:): the sources lockstep can follow.
  [[nodiscard]] bool is_socket() const { return kind == SourceKind::udp || kind == SourceKind::tcp; }
  [[nodiscard]] bool is_mavlink() const { return kind == SourceKind::mavlink_udp || kind == SourceKind::mavlink_tcp; }
  /// Sources whose poses are placed at their arrival time on the wall clock.
  [[nodiscard]] bool on_wall_clock() const { return is_socket() || is_mavlink(); }
};

/// The accepted forms, for messages.
inline constexpr std::string_view kSourceSpecForms =
    "sim:stationary, sim:line, sim:circle, sim:waypoints:FILE, replay:FILE.csv, udp:[HOST:]PORT, tcp:[HOST:]PORT, "
    "mavlink:udp:[HOST:]PORT, mavlink:tcp:HOST:PORT";

/// Parses one of kSourceSpecForms. Throws std::invalid_argument naming the spec ("unknown pose
/// source '...'", "--source udp:...: <why the address is bad>"). A sim scenario's name is checked
/// when the source is made.
[[nodiscard]] SourceSpec parse_source_spec(std::string_view text);

/// The spec as written.
[[nodiscard]] inline const std::string& to_string(const SourceSpec& spec) { return spec.text; }

}  // namespace gpsemu::sources
