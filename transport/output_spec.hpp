// Output specifications as a user writes them (`--output pty:/tmp/gpsemu`, `file:out.nmea`,
// `stdout`): a parser into a value, and a factory that opens the matching transport backend.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "transport/output.hpp"
#include "transport/serial_ports.hpp"

namespace gpsemu::transport {

/// Which backend a spec names.
enum class OutputKind {
  pty,              ///< `pty` or `pty:LINK`
  file,             ///< `file:PATH`
  standard_output,  ///< `stdout`
  serial,           ///< `serial:DEVICE[@BAUD]` or `serial:usb:VID:PID[:SERIAL][@BAUD]`
  tcp,              ///< `tcp:[HOST:]PORT`: a server NMEA clients connect to
  udp,              ///< `udp:HOST:PORT`: one datagram an epoch to HOST
};

struct OutputSpec {
  OutputKind kind = OutputKind::standard_output;
  /// pty: the stable symlink to create (empty: none); file: the file to create or truncate;
  /// serial: the device (empty when `usb` names the adapter).
  std::filesystem::path path;
  /// serial: the line's speed, bits per second, one of nmea::kStandardBauds (0: nmea::kDefaultBaud).
  int baud_bps = 0;
  /// tcp: the address to listen on (default 127.0.0.1); udp: where datagrams go.
  std::string host{};
  /// tcp: the port to listen on (0: any free port); udp: the destination port.
  std::uint16_t port = 0;
  /// serial: the USB adapter to find by identity (and to re-find after a replug).
  std::optional<UsbSelector> usb{};

  friend bool operator==(const OutputSpec&, const OutputSpec&) = default;
};

/// The accepted forms, for help texts and error messages.
inline constexpr std::string_view kOutputSpecForms =
    "pty[:LINK], file:PATH, stdout, serial:DEVICE[@BAUD], serial:usb:VID:PID[:SERIAL][@BAUD], "
    "tcp:[HOST:]PORT, udp:HOST:PORT";

/// Parses one of kOutputSpecForms. Throws std::invalid_argument naming the spec and listing the
/// accepted forms when it is unknown or malformed (a baud that is not a standard one, a bad port).
[[nodiscard]] OutputSpec parse_output_spec(std::string_view spec);

/// The spec written back in the form parse_output_spec() accepts.
[[nodiscard]] std::string to_string(const OutputSpec& spec);

struct OutputOptions {
  /// Real-time run (true) or batch generation with --fast (false): files and stdout hand every
  /// epoch to the operating system at once in real time, and buffer in large blocks otherwise.
  bool realtime = true;
  /// Epochs per second: a serial line queues at most one epoch period of bytes before it drops.
  double rate_hz = 1.0;
};

/// Opens the backend `spec` names. Throws std::runtime_error naming the path (device, address)
/// when it cannot.
[[nodiscard]] std::unique_ptr<Output> make_output(const OutputSpec& spec,
                                                  const OutputOptions& options);

}  // namespace gpsemu::transport
