// gpsemu-timing's inputs: the outputs it reads (ptys and serial devices, TCP servers, UDP
// ports with kernel receive time stamps), named by specs with {i}/{B+i} templates for many.
#pragma once

#include <string>
#include <utility>

namespace gpsemu::timing {

enum class Kind { device, tcp, udp };

[[nodiscard]] const char* kind_name(Kind k);

/// Expands "{i}" and "{B+i}" (B an integer) in `spec` for output i; throws on any other "{...}".
[[nodiscard]] std::string expand_template(const std::string& spec, int i);
/// Whether `spec` holds a template (expands differently for two outputs).
[[nodiscard]] bool has_template(const std::string& spec);

/// Opens a pty or serial device to read, raw and non-blocking. Throws naming it.
[[nodiscard]] int open_device(const std::string& path);
/// Connects to a TCP output at HOST:PORT, non-blocking. Throws naming it.
[[nodiscard]] int open_tcp(const std::string& host_port);
/// Binds a UDP socket on [HOST:]PORT (no host: every interface) with kernel receive time stamps
/// (SO_TIMESTAMPNS) and the kernel's drop count (SO_RXQ_OVFL). Throws naming it.
[[nodiscard]] int open_udp(const std::string& host_port);

}  // namespace gpsemu::timing
