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

std::unique_ptr<Output> make_output(const OutputSpec& spec, const OutputOptions& options) {
  switch (spec.kind) {
    case OutputKind::pty:
      return std::make_unique<PtyOutput>(spec.path.empty()
                                             ? std::nullopt
                                             : std::optional<std::filesystem::path>(spec.path));
    case OutputKind::file:
      return std::make_unique<FileOutput>(spec.path, options.realtime, spec.file_mode);
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
