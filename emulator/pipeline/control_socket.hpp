// The live control socket (--control unix:PATH or tcp:HOST:PORT): JSON lines in (faults/control.hpp), serviced by
// the epoch loop between epochs like the pose inputs, so a live fault applies at the next epoch
// and never delays one. What it refused or dropped (clients beyond the limit, idle or not reading,
// lines too long) and its ERROR answers are counted, logged (a few lines a second at most) and in
// the exit summary.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/common/log_limit.hpp"
#include "emulator/faults/control.hpp"
#include "emulator/pipeline/channel_set.hpp"
#include "transport/posix/unix_line_server.hpp"

namespace gpsemu {

class ControlSocket final : public LoopInput {
 public:
  /// Listens on `spec` (parse_control_spec(): a Unix socket's PATH, or "tcp:HOST:PORT") for the
  /// fault timelines of `channels`; a client silent for `idle_timeout` is closed (zero: never).
  /// Throws std::runtime_error.
  ControlSocket(const std::string& spec, ChannelSet& channels,
                std::chrono::milliseconds idle_timeout = posix::UnixLineServer::kDefaultIdleTimeout);
  void fds(std::vector<int>& out) const override;
  void service() override;
  [[nodiscard]] const posix::UnixLineServer& server() const { return server_; }
  /// ERROR answers given.
  [[nodiscard]] std::uint64_t error_answers() const { return error_answers_; }
  /// The status answer's additions for receiver i (faults::FaultControl::set_status_extra).
  void set_status_extra(std::function<std::string(std::size_t)> extra) { control_.set_status_extra(std::move(extra)); }
  /// Clients that asked {"watch":true}: they get receiver i's `line` (or every receiver's).
  [[nodiscard]] std::size_t watchers() const { return server_.watchers(); }
  void push(std::string_view line, std::size_t receiver) { server_.push(line, static_cast<std::int64_t>(receiver)); }
  /// The exit summary's line: requests answered, errors, clients refused and dropped.
  [[nodiscard]] std::string summary() const;

 private:
  /// Logs what the server refused or dropped since the last call (rate-limited).
  void log_drops();

  /// {"watch":true,"receiver":i}: makes the client a watcher; other lines go to control_.
  std::string answer(std::string_view line, std::optional<std::int64_t>& watch);

  faults::FaultControl control_;
  std::size_t receivers_ = 0;
  posix::UnixLineServer server_;
  /// Fires a few times an idle timeout, so idle clients are closed while nothing else wakes the loop.
  posix::UniqueFd idle_timer_;
  std::uint64_t error_answers_ = 0;
  posix::UnixLineServer::Stats logged_{};  ///< the counts the log has told
  std::uint64_t logged_shape_ = 0;
  LogLimit drop_log_{2};
  LogLimit error_log_{2};
};

/// gpsemu ctl's exchange: one request line to a control socket given as parse_control_spec()
/// accepts it (or a bare PATH), its answer line. Throws std::runtime_error.
[[nodiscard]] std::string control_request(const std::string& spec, std::string_view line, std::chrono::milliseconds timeout);
/// gpsemu ctl watch's exchange: `line`, then every answer line to `sink` until it returns false or
/// gpsemu closes. Throws std::runtime_error (no socket, nothing for `timeout`).
void control_watch(const std::string& spec, std::string_view line, std::chrono::milliseconds timeout,
                   const posix::LineSink& sink);

}  // namespace gpsemu
