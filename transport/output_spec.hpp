// Opening an output from its spec (emulator/config/spec/output_spec.hpp: the value a user writes,
// `--output pty:/tmp/gpsemu`, `file:out.nmea`, `stdout`): the factory of the matching backend.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "emulator/config/spec/output_spec.hpp"
#include "transport/file_output.hpp"
#include "transport/output.hpp"
#include "transport/serial_ports.hpp"

namespace gpsemu::transport {

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
