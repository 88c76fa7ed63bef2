// The live control socket (--control unix:PATH): JSON lines in (faults/control.hpp), serviced by
// the epoch loop between epochs like the pose inputs, so a live fault applies at the next epoch
// and never delays one.
#pragma once

#include <string>
#include <vector>

#include "emulator/faults/control.hpp"
#include "emulator/pipeline/channel_set.hpp"
#include "transport/posix/unix_line_server.hpp"

namespace gpsemu {

class ControlSocket final : public LoopInput {
 public:
  /// Listens on `path` for the fault timelines of `channels`. Throws std::runtime_error.
  ControlSocket(const std::string& path, ChannelSet& channels);
  void fds(std::vector<int>& out) const override { server_.fds(out); }
  void service() override {
    server_.service([this](std::string_view line) { return control_.handle(line); });
  }
  [[nodiscard]] const posix::UnixLineServer& server() const { return server_; }

 private:
  faults::FaultControl control_;
  posix::UnixLineServer server_;
};

/// "unix:PATH" -> PATH; throws std::invalid_argument otherwise.
[[nodiscard]] std::string parse_control_spec(const std::string& spec);

}  // namespace gpsemu
