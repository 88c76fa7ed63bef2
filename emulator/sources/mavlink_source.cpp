#include "emulator/sources/mavlink_source.hpp"

#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/sources/mavlink/stream_request.hpp"

namespace gpsemu::sources {
namespace {

/// How often a TCP-connected autopilot is asked to send its true state (50 Hz, as SITL bridges use).
constexpr std::chrono::microseconds kStateRequestInterval{20000};

using mavlink::FrameCounts;

double seconds(std::chrono::nanoseconds d) { return std::chrono::duration<double>(d).count(); }

LogLimit::Clock::time_point log_time(UtcNs t) {
  return LogLimit::Clock::time_point{
      std::chrono::duration_cast<LogLimit::Clock::duration>(t.time_since_epoch())};
}

/// The frame reader's problems, in the order of MavlinkPoseSource::frame_log_.
struct FrameKind {
  const char* name;
  std::uint64_t FrameCounts::*count;
};
constexpr std::array<FrameKind, 6> kFrameProblems{{
    {"bad_crc", &FrameCounts::bad_crc},
    {"bad_length", &FrameCounts::bad_length},
    {"signed_frame", &FrameCounts::signed_frame},
    {"unsupported_flags", &FrameCounts::unsupported_flags},
    {"partial_frame", &FrameCounts::partial_frame},
    {"garbage_bytes", &FrameCounts::garbage_bytes},
}};

/// How complete a message's truth is: a more complete one the owner sends wins.
int rank(std::uint32_t id) {
  switch (id) {
    case mavlink::kSimStateId: return 3;
    case mavlink::kHilStateQuaternionId: return 2;
    case mavlink::kSimstateId: return 1;
    default: return 0;
  }
}

std::size_t message_index(std::uint32_t id) {
  for (std::size_t i = 0; i < mavlink::kMessages.size(); ++i) {
    if (mavlink::kMessages[i].id == id) return i;
  }
  return 0;
}

}  // namespace

MavlinkPoseSource::MavlinkPoseSource(std::unique_ptr<transport::PoseSocket> socket, const LocalFrame& frame,
                                     const MavlinkSourceOptions& options)
    : socket_(std::move(socket)), frame_(frame), options_(options), history_(options.history) {
  reject_log_.fill(LogLimit(1));
  frame_log_.fill(LogLimit(1));
  spdlog::info("waiting for MAVLink SIM_STATE / HIL_STATE_QUATERNION / SIMSTATE on {}", socket_->describe());
}

MavlinkPoseSource::~MavlinkPoseSource() {
  spdlog::info("pose input mavlink:{}: {}", socket_->describe(), counts_text());
}

std::string MavlinkPoseSource::counts_text() const {
  std::string used;
  for (std::size_t i = 0; i < stats_.accepted_by_message.size(); ++i) {
    if (stats_.accepted_by_message[i] == 0) continue;
    used += fmt::format("{}{} {}", used.empty() ? " (" : ", ", mavlink::kMessages[i].name, stats_.accepted_by_message[i]);
  }
  if (!used.empty()) used += ")";
  std::string dropped;
  std::uint64_t dropped_total = 0;
  for (std::size_t i = 0; i < kPoseRejectCount; ++i) {
    if (stats_.rejected[i] == 0) continue;
    dropped_total += stats_.rejected[i];
    dropped += fmt::format(", {} {}", to_string(static_cast<PoseReject>(i)), stats_.rejected[i]);
  }
  const FrameCounts& f = reader_.counts();
  std::string bad;
  for (const FrameKind& k : kFrameProblems) {
    if (f.*k.count != 0) bad += fmt::format(", {} {}", k.name, f.*k.count);
  }
  return fmt::format("{} states used{}, {} dropped{}, {} superseded; frames: {} of these messages, {} of others{}; "
                     "{} sender changes, {} restarts, {} connections, {} lost{}{}",
                     stats_.accepted, used, dropped_total, dropped, stats_.superseded, f.frames, f.unknown_message, bad,
                     stats_.sender_changes, stats_.restarts, stats_.connections, stats_.disconnections,
                     stats_.datagrams_lost == 0
                         ? std::string()
                         : fmt::format("; {} datagrams dropped by the kernel (receive buffer full)", stats_.datagrams_lost),
                     stats_.stream_requests + stats_.failed_requests == 0
                         ? std::string()
                         : fmt::format("; states asked for on {} connections{}", stats_.stream_requests,
                                       stats_.failed_requests == 0
                                           ? std::string()
                                           : fmt::format(", {} requests not written", stats_.failed_requests)));
}

std::string MavlinkPoseSource::describe() const {
  return fmt::format("mavlink:{} (no fix after {} s without a state, extrapolation up to {} s)", socket_->describe(),
                     seconds(options_.history.timeout), seconds(options_.history.horizon));
}

void MavlinkPoseSource::service() {
  for (std::size_t i = 0; i < options_.max_messages_per_service; ++i) {
    const auto m = socket_->receive();
    if (!m) break;
    handle(*m);
    report_frames(m->arrival);
  }
}

void MavlinkPoseSource::handle(const transport::ReceivedMessage& m) {
  using Kind = transport::ReceivedMessage::Kind;
  switch (m.kind) {
    case Kind::message: {
      const auto* bytes = reinterpret_cast<const std::uint8_t*>(m.bytes.data());
      reader_.feed(std::span<const std::uint8_t>(bytes, m.bytes.size()));
      drain(m);
      if (options_.datagrams) {
        reader_.finish();
        drain(m);
      }
      return;
    }
    case Kind::kernel_dropped: return lost_datagrams(m);
    case Kind::too_large: return reject(PoseReject::too_large, m);
    case Kind::connected:
      ++stats_.connections;
      if (options_.request_interval.count() > 0) {
        if (socket_->reply(m.sender, mavlink::stream_request(options_.request_interval))) {
          ++stats_.stream_requests;
          spdlog::info("mavlink: asked {} for SIM_STATE and HIL_STATE_QUATERNION every {} ms", socket_->describe(),
                       options_.request_interval.count() / 1000.0);
        } else {
          ++stats_.failed_requests;
          spdlog::warn("mavlink: could not ask {} for its states (the request was not written whole)",
                       socket_->describe());
        }
      }
      return;
    case Kind::disconnected:
    case Kind::idle_closed:
    case Kind::taken_over:
    case Kind::partial_line:
    case Kind::refused_client:
      ++stats_.disconnections;
      reader_.finish();  // a frame cut by the drop is counted, the next connection starts clean
      drain(m);
      if (owner_ && owner_->sender == m.sender) owner_.reset();
      return;
  }
}

void MavlinkPoseSource::drain(const transport::ReceivedMessage& m) {
  while (const auto frame = reader_.next()) use(*frame, m);
  const std::uint64_t seen = reader_.counts().unknown_message + reader_.counts().frames;
  if (!warned_no_state_ && stats_.accepted == 0 && seen >= 500) {
    warned_no_state_ = true;
    spdlog::warn("pose input {}: {} MAVLink frames and none of SIM_STATE, HIL_STATE_QUATERNION or SIMSTATE: ask the "
                 "simulator to stream one (docs/pose-input.md)", socket_->describe(), seen);
  }
}

void MavlinkPoseSource::reject(PoseReject reason, const transport::ReceivedMessage& m, std::uint64_t count) {
  const auto i = static_cast<std::size_t>(reason);
  stats_.rejected[i] += count;
  unreported_[i] += count;
  if (!reject_log_[i].admit(log_time(m.arrival))) return;
  (void)reject_log_[i].take_suppressed();
  spdlog::warn("pose input: dropped {} from {}: {} ({} in all)",
               unreported_[i] == 1 ? "a MAVLink state" : fmt::format("{} MAVLink states", unreported_[i]),
               m.sender_name.empty() ? "?" : m.sender_name, to_string(reason), stats_.rejected[i]);
  unreported_[i] = 0;
}

void MavlinkPoseSource::lost_datagrams(const transport::ReceivedMessage& m) {
  stats_.datagrams_lost += m.count;
  unreported_lost_ += m.count;
  if (!lost_log_.admit(log_time(m.arrival))) return;
  (void)lost_log_.take_suppressed();
  spdlog::warn("mavlink: the kernel dropped {} datagram(s) (receive buffer full; what they held is unknown), {} in all",
               unreported_lost_, stats_.datagrams_lost);
  unreported_lost_ = 0;
}

void MavlinkPoseSource::report_frames(UtcNs now) {
  const FrameCounts& f = reader_.counts();
  for (std::size_t i = 0; i < kFrameProblems.size(); ++i) {
    const std::uint64_t total = f.*kFrameProblems[i].count;
    if (total == frame_reported_[i] || !frame_log_[i].admit(log_time(now))) continue;
    (void)frame_log_[i].take_suppressed();
    spdlog::warn("pose input {}: skipped {} more MAVLink {} ({} in all)", socket_->describe(),
                 total - frame_reported_[i], kFrameProblems[i].name, total);
    frame_reported_[i] = total;
  }
}

void MavlinkPoseSource::use(const mavlink::Frame& frame, const transport::ReceivedMessage& m) {
  if (const auto boot_ms = mavlink::attitude_time_boot_ms(frame)) {
    attitude_ = Attitude{Owner{m.sender, frame.system_id}, *boot_ms, m.arrival};
    return;
  }
  const mavlink::StateDecodeResult decoded = mavlink::decode_state(frame);
  if (const auto* why = std::get_if<PoseReject>(&decoded)) return reject(*why, m);
  const auto& state = std::get<mavlink::VehicleState>(decoded);

  const Owner sender{m.sender, frame.system_id};
  if (owner_ != sender) {
    if (owner_ && m.arrival - owner_last_ <= options_.history.timeout) return reject(PoseReject::other_sender, m);
    const std::string name = fmt::format("{} system {}", m.sender_name, frame.system_id);
    if (owner_ || !owner_name_.empty()) {
      ++stats_.sender_changes;
      spdlog::info("MAVLink vehicle is now {} (was {})", name, owner_name_);
    } else {
      spdlog::info("first MAVLink state ({}) from {}", mavlink::find_message(frame.message_id)->name, name);
    }
    history_.clear();
    owner_ = sender;
    owner_name_ = name;
    owner_best_rank_ = 0;
  }
  const int r = rank(frame.message_id);
  if (r < owner_best_rank_) {
    ++stats_.superseded;
    return;
  }
  if (r > owner_best_rank_ && owner_best_rank_ != 0) {
    // Not interpolated with the less complete message's poses (SIMSTATE has no altitude).
    spdlog::info("MAVLink: using {} from now on (more complete)", mavlink::find_message(frame.message_id)->name);
    history_.clear();
  }
  owner_best_rank_ = r;

  const Geodetic where{state.lat_deg, state.lon_deg, state.alt_msl_m.value_or(frame_.origin().alt_m)};
  std::optional<Enu> velocity;
  if (state.velocity) velocity = Enu{state.velocity->east_mps, state.velocity->north_mps, -state.velocity->down_mps};
  std::optional<double> sender_time_s;
  if (state.time_usec) sender_time_s = static_cast<double>(*state.time_usec) * 1e-6;
  // SIMSTATE has no time of its own: ArduPilot sends it right after an ATTITUDE, whose time_boot_ms
  // then times it (once), so speed from the track is right however bunched the arrivals are.
  if (!sender_time_s && attitude_ && attitude_->from == sender && m.arrival - attitude_->arrival <= kAttitudeFreshness) {
    sender_time_s = attitude_->time_boot_ms * 1e-3;
    attitude_.reset();
  }
  const TimedPose timed{m.arrival, sender_time_s, frame_.to_enu(where), velocity, state.yaw_deg,
                        Tilt{state.pitch_deg, state.roll_deg}};
  const PushResult pushed = history_.push(timed);
  if (const auto why = refusal_of(pushed)) return reject(*why, m);
  if (pushed == PushResult::restarted) {
    ++stats_.restarts;
    spdlog::warn("pose input: MAVLink time or clock went back (simulator restarted?): pose history cleared");
  }
  ++stats_.accepted;
  ++stats_.accepted_by_message[message_index(frame.message_id)];
  owner_last_ = m.arrival;
}

std::optional<Truth> MavlinkPoseSource::truth_at(UtcNs t) {
  std::optional<Truth> truth = history_.sample(t);
  transitions_.note(truth.has_value(), t, history_, owner_name_);
  return truth;
}

std::unique_ptr<PoseSource> make_mavlink_source(bool udp, const transport::PoseEndpoint& endpoint,
                                                const LocalFrame& frame, const PoseHistoryOptions& history) {
  // A MAVLink 2 frame is at most 280 bytes; a datagram may hold several.
  const transport::PoseSocketOptions socket_options{.max_message_bytes = 65535, .max_clients = 1};
  std::unique_ptr<transport::PoseSocket> socket = udp ? transport::open_udp_pose_socket(endpoint, socket_options)
                                                      : transport::open_tcp_pose_client(endpoint, socket_options);
  return std::make_unique<MavlinkPoseSource>(std::move(socket), frame,
                                             MavlinkSourceOptions{.history = history, .datagrams = udp,
                                                                  .request_interval = udp ? std::chrono::microseconds{0}
                                                                                          : kStateRequestInterval});
}

}  // namespace gpsemu::sources
