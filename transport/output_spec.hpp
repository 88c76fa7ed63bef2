// Output specifications as a user writes them (`--output pty:/tmp/gpsemu`, `file:out.nmea`,
// `stdout`): a parser into a value, and a factory that opens the matching transport backend.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "transport/output.hpp"

namespace gpsemu::transport {

/// Which backend a spec names. Planned: serial (`serial:DEVICE[@BAUD]`), tcp (`tcp:[HOST:]PORT`),
/// udp (`udp:HOST:PORT`); they will add `baud_bps`, `host` and `port` fields beside `path`.
enum class OutputKind {
  pty,              ///< `pty` or `pty:LINK`
  file,             ///< `file:PATH`
  standard_output,  ///< `stdout`
};

struct OutputSpec {
  OutputKind kind = OutputKind::standard_output;
  /// pty: the stable symlink to create (empty: none); file: the file to create or truncate.
  std::filesystem::path path;

  friend bool operator==(const OutputSpec&, const OutputSpec&) = default;
};

/// The accepted forms, for help texts and error messages.
inline constexpr std::string_view kOutputSpecForms = "pty[:LINK], file:PATH, stdout";

/// Parses "pty", "pty:LINK", "file:PATH" or "stdout". Throws std::invalid_argument naming the
/// spec and listing the accepted forms when it is unknown or malformed.
[[nodiscard]] OutputSpec parse_output_spec(std::string_view spec);

/// The spec written back in the form parse_output_spec() accepts.
[[nodiscard]] std::string to_string(const OutputSpec& spec);

struct OutputOptions {
  /// Real-time run (true) or batch generation with --fast (false): files and stdout hand every
  /// epoch to the operating system at once in real time, and buffer in large blocks otherwise.
  bool realtime = true;
};

/// Opens the backend `spec` names. Throws std::runtime_error naming the path when it cannot.
[[nodiscard]] std::unique_ptr<Output> make_output(const OutputSpec& spec,
                                                  const OutputOptions& options);

}  // namespace gpsemu::transport
