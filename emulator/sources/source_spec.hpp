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
};

struct SourceSpec {
  SourceKind kind = SourceKind::sim;
  /// sim: the scenario as make_sim_source() takes it ("stationary", "line", "circle", "waypoints:FILE").
  std::string scenario = "stationary";
  std::filesystem::path path;         ///< replay: the trajectory CSV file
  transport::PoseEndpoint endpoint;   ///< udp, tcp: where to listen
  std::string text = "sim:stationary";  ///< the spec as written (for messages)

  [[nodiscard]] bool is_socket() const { return kind == SourceKind::udp || kind == SourceKind::tcp; }
};

/// The accepted forms, for messages.
inline constexpr std::string_view kSourceSpecForms =
    "sim:stationary, sim:line, sim:circle, sim:waypoints:FILE, replay:FILE.csv, udp:[HOST:]PORT, tcp:[HOST:]PORT";

/// Parses one of kSourceSpecForms. Throws std::invalid_argument naming the spec ("unknown pose
/// source '...'", "--source udp:...: <why the address is bad>"). A sim scenario's name is checked
/// when the source is made.
[[nodiscard]] SourceSpec parse_source_spec(std::string_view text);

/// The spec as written.
[[nodiscard]] inline const std::string& to_string(const SourceSpec& spec) { return spec.text; }

}  // namespace gpsemu::sources
