// Output specifications as a user writes them (`--output pty:/tmp/gpsemu`, `file:out.nmea`,
// `stdout`, `serial:usb:0403:6001@115200`): the value, its parser and its text. Pure: the transport
// opens the backend a spec names (transport/output_spec.hpp: make_output).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace gpsemu::transport {

/// What a file output does with an existing file (`file:PATH?mode=...`). Every mode follows a
/// symlink at PATH to its target.
enum class FileMode {
  truncate,    ///< the default: truncated when the run starts (commit()); created when missing
  append,      ///< written after what it holds (O_APPEND); created when missing
  create_new,  ///< `new`: must not exist yet (a symlink, even a dangling one, counts as existing)
};

/// "truncate", "append", "new".
[[nodiscard]] std::string_view to_string(FileMode mode);

/// A USB adapter's identity as a spec names it: `VID:PID[:SERIAL]` (hexadecimal IDs).
struct UsbSelector {
  std::uint16_t vid = 0;
  std::uint16_t pid = 0;
  std::string serial;  ///< empty: any serial number

  friend bool operator==(const UsbSelector&, const UsbSelector&) = default;
};

/// Parses "0403:6001" or "0403:6001:A10KZ3QF" (IDs: 1-4 hexadecimal digits). Throws
/// std::invalid_argument saying what is wrong with `text`.
[[nodiscard]] UsbSelector parse_usb_selector(std::string_view text);

/// "0403:6001" or "0403:6001:A10KZ3QF" (lower-case hex, four digits).
[[nodiscard]] std::string to_string(const UsbSelector& selector);

/// Which backend a spec names.
enum class OutputKind {
  pty,              ///< `pty` or `pty:LINK`
  file,             ///< `file:PATH[?mode=append|new]`
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
  /// file: what to do with an existing file (`?mode=append|new`; default: truncate it).
  FileMode file_mode = FileMode::truncate;

  friend bool operator==(const OutputSpec&, const OutputSpec&) = default;
};

/// The accepted forms, for help texts and error messages.
inline constexpr std::string_view kOutputSpecForms =
    "pty[:LINK], file:PATH[?mode=append|new], stdout, serial:DEVICE[@BAUD], serial:usb:VID:PID[:SERIAL][@BAUD], "
    "tcp:[HOST:]PORT, udp:HOST:PORT";

/// Parses one of kOutputSpecForms. Throws std::invalid_argument naming the spec and listing the
/// accepted forms when it is unknown or malformed (a baud that is not a standard one, a bad port).
[[nodiscard]] OutputSpec parse_output_spec(std::string_view spec);

/// The spec written back in the form parse_output_spec() accepts.
[[nodiscard]] std::string to_string(const OutputSpec& spec);

}  // namespace gpsemu::transport
