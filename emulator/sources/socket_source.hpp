// The udp: and tcp: pose sources: an external simulator (Chrono/PyChrono, Gazebo, CARLA, the
// user's own loop) sends JSON poses (pose_message.hpp) to a pose socket (transport/); each epoch
// reports the truth sampled from the pose history (pose_history.hpp).
//
// - Time base: a pose holds at its arrival time on CLOCK_REALTIME (UTC), so epoch t reports the
//   pose the simulator sent around t (interpolated; the epoch is sampled at t + latency). A pose
//   with its own `t` holds where sender_clock.hpp puts it: by the sender's spacing, never later than
//   its arrival, so a late read of queued TCP lines does not make them all hold at the read time.
//   Lockstep time base (--clock lockstep, SocketSourceOptions::sender_time_base): a pose holds at
//   base + its `t` instead, poses without `t` are refused (missing_key), and sim_time() tells the
//   lockstep clock how far the simulator has got.
// - One sender at a time: the first sender (UDP source address:port, or TCP connection) owns the
//   stream; another sender's poses are dropped (other_sender) until the owner has been silent for
//   the pose timeout or, over TCP, has disconnected. Then the next sender takes over with a fresh
//   history.
// - Bad input is dropped, counted per reason, logged at most once a second per reason; the last
//   good pose stays. TCP connections, disconnections and idle clients closed (transport's idle
//   timeout and take-over) are counted and logged at most once a second per kind, with counts. service() handles at most max_messages_per_service messages a call.
// - Staleness: no truth once the newest pose is older than the timeout; each transition is logged
//   once. The counts are logged when the source is destroyed.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "emulator/common/log_limit.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/sources/fix_transitions.hpp"
#include "emulator/sources/pose_history.hpp"
#include "emulator/sources/pose_message.hpp"
#include "emulator/sources/pose_source.hpp"
#include "emulator/sources/sender_clock.hpp"
#include "transport/input/pose_socket.hpp"

namespace gpsemu::sources {

struct SocketSourceOptions {
  PoseHistoryOptions history;                   ///< timeout, extrapolation horizon, capacity
  std::size_t max_messages_per_service = 256;   ///< socket events handled per service() call
  /// Lockstep: poses hold at this UTC + their `t` (seconds) instead of their arrival time.
  std::optional<UtcNs> sender_time_base;
};

/// Counters of a socket pose source.
struct SocketSourceStats {
  std::uint64_t accepted = 0;                                 ///< poses put in the history
  std::array<std::uint64_t, kPoseRejectCount> rejected{};     ///< dropped, by PoseReject
  std::uint64_t sender_changes = 0;                           ///< times another sender took over
  std::uint64_t restarts = 0;                                 ///< history cleared: sender time or clock went back
  std::uint64_t connections = 0;                              ///< TCP connections taken
  std::uint64_t disconnections = 0;                           ///< TCP connections closed by their client
  std::uint64_t idle_closed = 0;                              ///< TCP clients closed after the idle timeout
  std::uint64_t taken_over = 0;                               ///< idle TCP clients closed for a newcomer
  [[nodiscard]] std::uint64_t rejected_total() const;
};

class SocketPoseSource final : public PoseSource {
 public:
  SocketPoseSource(std::unique_ptr<transport::PoseSocket> socket, const LocalFrame& frame,
                   const SocketSourceOptions& options);
  ~SocketPoseSource() override;  ///< logs the counters

  std::optional<Truth> truth_at(UtcNs t) override;
  void service() override;
  int poll_fd() const override { return socket_->poll_fd(); }
  std::string describe() const override;
  /// Lockstep: the newest pose's time (base + t); otherwise nothing.
  std::optional<UtcNs> sim_time() const override;

  [[nodiscard]] const SocketSourceStats& stats() const { return stats_; }

 private:
  void handle_message(const transport::ReceivedMessage& m);
  void reject(PoseReject reason, const transport::ReceivedMessage& m, std::uint64_t count = 1);
  /// A TCP connection came or went: counted in `total`, logged at most once a second per kind.
  void note_connection(const transport::ReceivedMessage& m, std::uint64_t& total);
  [[nodiscard]] Enu to_local(const PoseMessage& pose) const;

  std::unique_ptr<transport::PoseSocket> socket_;
  LocalFrame frame_;
  SocketSourceOptions options_;
  PoseHistory history_;
  SenderClock sender_clock_;  ///< outside lockstep: where a pose with its own `t` holds
  SocketSourceStats stats_;
  FixTransitions transitions_{"pose", "poses"};
  std::optional<std::uint64_t> owner_;  ///< sender of the history's poses
  std::string owner_name_;
  UtcNs owner_last_{};                  ///< arrival of the owner's newest accepted pose
  /// Refused messages, a line a second for each reason (the shared limiter, on arrival times).
  std::array<LogLimit, kPoseRejectCount> reject_log_ = one_a_second<kPoseRejectCount>();
  std::array<std::uint64_t, kPoseRejectCount> unreported_{};
  /// Connection notes, indexed by transport::ReceivedMessage::Kind (connected .. taken_over).
  static constexpr std::size_t kNoteKinds = 9;
  std::array<LogLimit, kNoteKinds> note_log_ = one_a_second<kNoteKinds>();
  std::array<std::uint64_t, kNoteKinds> unnoted_{};

  template <std::size_t N>
  static std::array<LogLimit, N> one_a_second() {
    std::array<LogLimit, N> limits;
    limits.fill(LogLimit(1));
    return limits;
  }
};

/// Builds a source listening on `endpoint`: a UDP receiver (`udp`) or a TCP server. Throws
/// std::runtime_error naming host:port when the socket cannot be bound.
[[nodiscard]] std::unique_ptr<PoseSource> make_socket_source(bool udp, const transport::PoseEndpoint& endpoint,
                                                             const LocalFrame& frame,
                                                             const SocketSourceOptions& options);

}  // namespace gpsemu::sources
