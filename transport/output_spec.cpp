#include "transport/output_spec.hpp"

#include <fmt/format.h>

#include <optional>
#include <stdexcept>

#include "transport/file_output.hpp"
#include "transport/pty_output.hpp"

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
  if (kind == "serial" || kind == "tcp" || kind == "udp") {
    reject(spec, fmt::format("{} output is not supported yet", kind));
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
  }
  throw std::invalid_argument(
      fmt::format("make_output: unknown output kind {}", static_cast<int>(spec.kind)));
}

}  // namespace gpsemu::transport
