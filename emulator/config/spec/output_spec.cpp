#include "emulator/config/spec/output_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <stdexcept>

#include "emulator/config/spec/endpoint.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu::transport {

std::string_view to_string(FileMode mode) {
  switch (mode) {
    case FileMode::truncate: return "truncate";
    case FileMode::append: return "append";
    case FileMode::create_new: return "new";
  }
  return "?";
}

namespace {

std::uint16_t parse_hex_id(std::string_view text, std::string_view whole, const char* what) {
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, 16);
  if (text.empty() || text.size() > 4 || ec != std::errc{} || end != text.data() + text.size()) {
    throw std::invalid_argument(fmt::format(
        "'{}': the USB {} must be 1 to 4 hexadecimal digits (e.g. 0403:6001), got '{}'", whole, what, text));
  }
  return static_cast<std::uint16_t>(value);
}

}  // namespace

UsbSelector parse_usb_selector(std::string_view text) {
  UsbSelector s;
  const std::size_t first = text.find(':');
  if (first == std::string_view::npos) {
    throw std::invalid_argument(fmt::format("'{}': expected VID:PID[:SERIAL], e.g. 0403:6001", text));
  }
  const std::size_t second = text.find(':', first + 1);
  s.vid = parse_hex_id(text.substr(0, first), text, "vendor ID");
  s.pid = parse_hex_id(text.substr(first + 1, second == std::string_view::npos ? std::string_view::npos
                                                                                : second - first - 1),
                       text, "product ID");
  if (second != std::string_view::npos) {
    s.serial = std::string(text.substr(second + 1));
    if (s.serial.empty()) {
      throw std::invalid_argument(fmt::format("'{}': empty serial number after VID:PID:", text));
    }
  }
  return s;
}

std::string to_string(const UsbSelector& selector) {
  std::string out = fmt::format("{:04x}:{:04x}", selector.vid, selector.pid);
  if (!selector.serial.empty()) out += ":" + selector.serial;
  return out;
}

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

/// file:PATH[?mode=truncate|append|new]: `value` is what follows "file:". A '?' not followed by
/// "mode=" is part of the path.
OutputSpec parse_file(std::string_view spec, std::string_view value) {
  OutputSpec out{OutputKind::file, {}};
  std::string_view path = value;
  if (const std::size_t q = value.rfind('?'); q != std::string_view::npos && value.substr(q + 1, 5) == "mode=") {
    path = value.substr(0, q);
    const std::string_view mode = value.substr(q + 6);
    if (mode == "append") {
      out.file_mode = FileMode::append;
    } else if (mode == "new") {
      out.file_mode = FileMode::create_new;
    } else if (mode != "truncate") {
      reject(spec, fmt::format("file mode '{}' is not one of truncate (the default), append, new", printable(mode)));
    }
  }
  out.path = checked_path(spec, "file:PATH", path);
  return out;
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
    return parse_file(spec, *value);
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
      if (spec.file_mode == FileMode::truncate) return "file:" + spec.path.string();
      return fmt::format("file:{}?mode={}", spec.path.string(), to_string(spec.file_mode));
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

}  // namespace gpsemu::transport
