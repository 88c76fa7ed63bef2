// The mavlink: pose source: a simulator's MAVLink stream (ArduPilot SITL, PX4 SITL) carries the
// vehicle's true state in SIM_STATE, HIL_STATE_QUATERNION or SIMSTATE (mavlink/vehicle_state.hpp);
// each epoch reports the truth sampled from the same pose history the JSON poses use
// (pose_history.hpp: interpolation, extrapolation up to the horizon, no fix after the timeout,
// jumps, floods and reordering refused).
//
// - Input: `mavlink:udp:[HOST:]PORT` listens for datagrams (each a whole number of frames; a frame
//   cut by a datagram's end is dropped); `mavlink:tcp:HOST:PORT` connects (SITL's 5760) and
//   reconnects after a drop, frames may span reads; on each connection it asks, as a ground station
//   would, for SIM_STATE and HIL_STATE_QUATERNION at 50 Hz (stream_request.hpp: ArduPilot sends
//   SIM_STATE in no default stream, PX4 its ground truth only when asked).
// - Time base: arrival time on CLOCK_REALTIME, as JSON poses (UDP: the kernel's time stamp).
//   HIL_STATE_QUATERNION's time_usec plays the role of a JSON pose's `t` (reordering, track speed);
//   a SIMSTATE's is the time_boot_ms of the ATTITUDE ArduPilot sends just before it (when one came
//   from the same system within kAttitudeFreshness), so bursty links do not make its track speed wild.
// - One vehicle: the first system (its MAVLink system id, from one UDP sender or TCP connection)
//   that sends a state owns the stream; other systems' states are dropped (other_sender) until the
//   owner has been silent for the pose timeout. Of the three messages, the most complete one the
//   owner sends is used (SIM_STATE, then HIL_STATE_QUATERNION, then SIMSTATE): ArduPilot sends
//   SIMSTATE and SIM_STATE together, and SIMSTATE carries no altitude or velocity.
// - Bad input: frames with a bad CRC or length, signed frames, unknown incompat flags, partial
//   frames and stray bytes are skipped and counted (mavlink_frame.hpp); states out of range are
//   dropped by the JSON poses' reasons; every kind is logged at most once a second and listed in
//   the summary when the source is destroyed. Frames of other messages are counted, not logged.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "emulator/common/log_limit.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/sources/fix_transitions.hpp"
#include "emulator/sources/mavlink/mavlink_frame.hpp"
#include "emulator/sources/mavlink/vehicle_state.hpp"
#include "emulator/sources/pose_history.hpp"
#include "emulator/sources/pose_source.hpp"
#include "transport/input/pose_socket.hpp"

namespace gpsemu::sources {

struct MavlinkSourceOptions {
  PoseHistoryOptions history;                   ///< timeout, extrapolation horizon, capacity
  std::size_t max_messages_per_service = 256;   ///< socket reads handled per service() call
  bool datagrams = true;                        ///< UDP: each message ends its frames
  /// TCP: on each connection, ask the autopilot for SIM_STATE and HIL_STATE_QUATERNION at this
  /// interval (mavlink/stream_request.hpp); 0: ask nothing.
  std::chrono::microseconds request_interval{0};
};

/// Counters of a MAVLink pose source (the frame reader's are in frames()).
struct MavlinkSourceStats {
  std::uint64_t accepted = 0;                                ///< states put in the history
  std::array<std::uint64_t, 3> accepted_by_message{};        ///< in mavlink::kMessages order
  std::array<std::uint64_t, kPoseRejectCount> rejected{};    ///< dropped, by PoseReject
  std::uint64_t superseded = 0;   ///< states of a less complete message than the owner also sends
  std::uint64_t sender_changes = 0;
  std::uint64_t restarts = 0;
  std::uint64_t connections = 0;     ///< TCP connections made
  std::uint64_t disconnections = 0;  ///< TCP connections lost
  std::uint64_t stream_requests = 0;  ///< TCP: connections the states were asked for on
  std::uint64_t failed_requests = 0;  ///< TCP: requests that could not be written whole
  /// UDP datagrams the kernel dropped (receive buffer full): what they held is unknown (a state, a
  /// heartbeat, anything), so they are counted apart from the states dropped.
  std::uint64_t datagrams_lost = 0;
};

class MavlinkPoseSource final : public PoseSource {
 public:
  MavlinkPoseSource(std::unique_ptr<transport::PoseSocket> socket, const LocalFrame& frame,
                    const MavlinkSourceOptions& options);
  ~MavlinkPoseSource() override;  ///< logs the counters

  std::optional<Truth> truth_at(UtcNs t) override;
  void service() override;
  int poll_fd() const override { return socket_->poll_fd(); }
  std::string describe() const override;

  [[nodiscard]] const MavlinkSourceStats& stats() const { return stats_; }
  [[nodiscard]] const mavlink::FrameCounts& frames() const { return reader_.counts(); }
  /// "SIM_STATE 120, ...; dropped ...; frames: ..." (the summary's counts).
  [[nodiscard]] std::string counts_text() const;

 private:
  void handle(const transport::ReceivedMessage& m);
  void drain(const transport::ReceivedMessage& m);
  void use(const mavlink::Frame& frame, const transport::ReceivedMessage& m);
  void reject(PoseReject reason, const transport::ReceivedMessage& m, std::uint64_t count = 1);
  /// UDP datagrams the kernel dropped: counted (stats_.datagrams_lost), a line a second at most.
  void lost_datagrams(const transport::ReceivedMessage& m);
  /// Frame-level problems since the last call, logged at most once a second per kind.
  void report_frames(UtcNs now);

  struct Owner {
    std::uint64_t sender = 0;
    std::uint8_t system_id = 0;
    bool operator==(const Owner&) const = default;
  };

  std::unique_ptr<transport::PoseSocket> socket_;
  LocalFrame frame_;
  MavlinkSourceOptions options_;
  PoseHistory history_;
  mavlink::FrameReader reader_;
  MavlinkSourceStats stats_;
  FixTransitions transitions_{"MAVLink state", "MAVLink states"};
  std::optional<Owner> owner_;
  std::string owner_name_;
  UtcNs owner_last_{};
  int owner_best_rank_ = 0;  ///< the most complete message the owner has sent (3 SIM_STATE .. 1 SIMSTATE)
  /// The last ATTITUDE not yet used to time a state: who sent it, its time_boot_ms, its arrival.
  struct Attitude {
    Owner from;
    std::uint32_t time_boot_ms = 0;
    UtcNs arrival{};
  };
  std::optional<Attitude> attitude_;
  /// An ATTITUDE times the state that arrives within this after it (sent in the same tick).
  static constexpr std::chrono::milliseconds kAttitudeFreshness{100};
  std::array<LogLimit, kPoseRejectCount> reject_log_;
  std::array<std::uint64_t, kPoseRejectCount> unreported_{};
  LogLimit lost_log_{1};
  std::uint64_t unreported_lost_ = 0;
  static constexpr std::size_t kFrameKinds = 6;  ///< bad_crc .. partial_frame, garbage
  std::array<LogLimit, kFrameKinds> frame_log_;
  std::array<std::uint64_t, kFrameKinds> frame_reported_{};
  bool warned_no_state_ = false;
};

/// Builds a source on `endpoint`: a UDP receiver (`udp`) or a TCP client that connects to it.
/// Throws std::runtime_error naming host:port when the socket cannot be bound or the host resolved.
[[nodiscard]] std::unique_ptr<PoseSource> make_mavlink_source(bool udp, const transport::PoseEndpoint& endpoint,
                                                              const LocalFrame& frame,
                                                              const PoseHistoryOptions& history);

}  // namespace gpsemu::sources
