// Who wrote to a receiver: one connection to an output (a TCP client, whoever has a pty open, a
// new one after every client closed it, or the serial line), unique in the process. The outputs
// give them (transport/output.hpp: new_client_id()); the protocols answer each by it.
#pragma once

#include <cstdint>

namespace gpsemu {

using ClientId = std::uint64_t;

}  // namespace gpsemu
