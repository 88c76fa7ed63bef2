// The live control socket (--control unix:PATH or tcp:HOST:PORT): JSON lines in (faults/control.hpp), serviced by
// the epoch loop between epochs like the pose inputs, so a live fault applies at the next epoch
// and never delays one.
#pragma once

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/faults/control.hpp"
#include "emulator/pipeline/channel_set.hpp"
#include "transport/posix/unix_line_server.hpp"

namespace gpsemu {

class ControlSocket final : public LoopInput {
 public:
  /// Listens on `spec` (parse_control_spec(): a Unix socket's PATH, or "tcp:HOST:PORT") for the
  /// fault timelines of `channels`. Throws std::runtime_error.
  ControlSocket(const std::string& spec, ChannelSet& channels);
  void fds(std::vector<int>& out) const override { server_.fds(out); }
  void service() override {
    server_.service([this](std::string_view line) { return control_.handle(line); });
  }
  [[nodiscard]] const posix::UnixLineServer& server() const { return server_; }

 private:
  faults::FaultControl control_;
  posix::UnixLineServer server_;
};

/// "unix:PATH" -> PATH; "tcp:[HOST:]PORT" -> "tcp:HOST:PORT" (HOST default 127.0.0.1; port 0: the
/// system picks one, logged at start-up); throws std::invalid_argument otherwise.
[[nodiscard]] std::string parse_control_spec(const std::string& spec);
/// gpsemu ctl's exchange: one request line to a control socket given as parse_control_spec()
/// accepts it (or a bare PATH), its answer line. Throws std::runtime_error.
[[nodiscard]] std::string control_request(const std::string& spec, std::string_view line, std::chrono::milliseconds timeout);

}  // namespace gpsemu
