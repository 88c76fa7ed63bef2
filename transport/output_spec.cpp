#include "transport/output_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <optional>
#include <stdexcept>

#include "nmea/line_budget.hpp"
#include "transport/file_output.hpp"
#include "transport/posix/sockets.hpp"
#include "transport/pty_output.hpp"
#include "transport/serial_output.hpp"
#include "transport/tcp_output.hpp"
#include "transport/udp_output.hpp"

namespace gpsemu::transport {

namespace {

/// The spec as it can be shown in a message: control bytes (a NUL would cut the message) as \xNN.
std::string printable(std::string_view spec) {
  std::string out;
  for (const char c : spec) {
    const auto byte = static_cast<unsigned char>(c);
    out += byte < 0x20 || byte == 0x7f ? fmt::format("\\x{:02x}", byte) : std::string(1, c);
  }
  return out;
}

[[noreturn]] void reject(std::string_view spec, std::string_view why) {
  throw std::invalid_argument(fmt::format("invalid output spec '{}': {}; accepted forms: {}",
                                          printable(spec), why, kOutputSpecForms));
}

std::filesystem::path checked_path(std::string_view spec, std::string_view kind,
                                   std::string_view value) {
  if (value.empty()) reject(spec, fmt::format("{}: needs a path after the colon", kind));
  if (value.find('\0') != std::string_view::npos) reject(spec, "the path contains a NUL byte");
  return std::filesystem::path(std::string(value));
}

bool all_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// serial:DEVICE[@BAUD] or serial:usb:VID:PID[:SERIAL][@BAUD]: `value` is what follows "serial:".
OutputSpec parse_serial(std::string_view spec, std::string_view value) {
  OutputSpec out{OutputKind::serial, {}};
  std::string_view target = value;
  if (const std::size_t at = value.rfind('@'); at != std::string_view::npos && all_digits(value.substr(at + 1))) {
    target = value.substr(0, at);
    const std::string_view baud = value.substr(at + 1);
    int bps = 0;
    const auto [end, ec] = std::from_chars(baud.data(), baud.data() + baud.size(), bps);
    if (ec != std::errc{} || end != baud.data() + baud.size() || !nmea::is_standard_baud(bps)) {
      reject(spec, fmt::format("baud {} is not supported; use one of {}", baud, nmea::standard_bauds_text()));
    }
    out.baud_bps = bps;
  } else if (at != std::string_view::npos && at + 1 == value.size()) {
    reject(spec, "needs a baud after '@' (serial:DEVICE@BAUD)");
  }
  if (target.substr(0, 4) == "usb:") {
    try {
      out.usb = parse_usb_selector(target.substr(4));
    } catch (const std::invalid_argument& e) {
      reject(spec, fmt::format("serial:usb:VID:PID[:SERIAL]: {}", e.what()));
    }
    return out;
  }
  out.path = checked_path(spec, "serial:DEVICE", target);
  return out;
}

/// tcp:[HOST:]PORT or udp:HOST:PORT: `value` is what follows the colon.
OutputSpec parse_network(std::string_view spec, OutputKind kind, std::string_view value) {
  const bool udp = kind == OutputKind::udp;
  if (value.empty()) reject(spec, udp ? "udp needs HOST:PORT" : "tcp needs [HOST:]PORT");
  if (udp && value.find(':') == std::string_view::npos) {
    reject(spec, "udp needs a destination host: udp:HOST:PORT (e.g. udp:127.0.0.1:10110)");
  }
  posix::Endpoint endpoint;
  try {
    endpoint = posix::parse_endpoint(value);
  } catch (const std::invalid_argument& e) {
    reject(spec, e.what());
  }
  if (udp && endpoint.port == 0) reject(spec, "udp needs a destination port from 1 to 65535");
  OutputSpec out{kind, {}};
  // Without a host a tcp server listens on the default (127.0.0.1); the spec keeps it unset so
  // it reads back as written.
  const bool host_given = value.find(':') != std::string_view::npos;
  out.host = host_given ? endpoint.host : std::string();
  out.port = endpoint.port;
  return out;
}

std::string host_port(const std::string& host, std::uint16_t port) {
  if (host.empty()) return std::to_string(port);
  return posix::host_port(host, port);
}

}  // namespace

OutputSpec parse_output_spec(std::string_view spec) {
  const std::size_t colon = spec.find(':');
  const std::string_view kind = spec.substr(0, colon);
  const std::optional<std::string_view> value =
      colon == std::string_view::npos ? std::nullopt : std::optional(spec.substr(colon + 1));

  if (kind == "pty") {
    if (!value) return OutputSpec{OutputKind::pty, {}};
    return OutputSpec{OutputKind::pty, checked_path(spec, "pty:LINK", *value)};
  }
  if (kind == "file") {
    if (!value) reject(spec, "file output needs a path (file:PATH)");
    return OutputSpec{OutputKind::file, checked_path(spec, "file:PATH", *value)};
  }
  if (kind == "stdout") {
    if (value) reject(spec, "stdout takes no argument");
    return OutputSpec{OutputKind::standard_output, {}};
  }
  if (kind == "serial") {
    if (!value || value->empty()) reject(spec, "serial needs a device: serial:DEVICE[@BAUD] or serial:usb:VID:PID");
    return parse_serial(spec, *value);
  }
  if (kind == "tcp" || kind == "udp") {
    if (value && value->find('\0') != std::string_view::npos) reject(spec, "the address contains a NUL byte");
    return parse_network(spec, kind == "tcp" ? OutputKind::tcp : OutputKind::udp, value.value_or(""));
  }
  if (spec.empty()) reject(spec, "empty");
  reject(spec, fmt::format("unknown output kind '{}'", kind));
}

std::string to_string(const OutputSpec& spec) {
  switch (spec.kind) {
    case OutputKind::pty:
      return spec.path.empty() ? "pty" : "pty:" + spec.path.string();
    case OutputKind::file:
      return "file:" + spec.path.string();
    case OutputKind::standard_output:
      return "stdout";
    case OutputKind::serial: {
      std::string out = "serial:" + (spec.usb ? "usb:" + to_string(*spec.usb) : spec.path.string());
      if (spec.baud_bps != 0) out += "@" + std::to_string(spec.baud_bps);
      return out;
    }
    case OutputKind::tcp:
      return "tcp:" + host_port(spec.host, spec.port);
    case OutputKind::udp:
      return "udp:" + host_port(spec.host, spec.port);
  }
  return "?";
}

std::unique_ptr<Output> make_output(const OutputSpec& spec, const OutputOptions& options) {
  switch (spec.kind) {
    case OutputKind::pty:
      return std::make_unique<PtyOutput>(spec.path.empty()
                                             ? std::nullopt
                                             : std::optional<std::filesystem::path>(spec.path));
    case OutputKind::file:
      return std::make_unique<FileOutput>(spec.path, options.realtime);
    case OutputKind::standard_output:
      return FileOutput::to_stdout(options.realtime);
    case OutputKind::serial: {
      SerialOptions serial;
      serial.baud_bps = spec.baud_bps != 0 ? spec.baud_bps : nmea::kDefaultBaud;
      serial.max_queue_s = options.rate_hz > 0.0 ? 1.0 / options.rate_hz : 1.0;
      return std::make_unique<SerialOutput>(SerialTarget{spec.path, spec.usb}, serial);
    }
    case OutputKind::tcp:
      return std::make_unique<TcpOutput>(spec.host.empty() ? "127.0.0.1" : spec.host, spec.port);
    case OutputKind::udp:
      return std::make_unique<UdpOutput>(spec.host, spec.port);
  }
  throw std::invalid_argument(
      fmt::format("make_output: unknown output kind {}", static_cast<int>(spec.kind)));
}

}  // namespace gpsemu::transport
