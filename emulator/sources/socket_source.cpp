#include "emulator/sources/socket_source.hpp"

#include <cctype>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace gpsemu::sources {
namespace {

double seconds(std::chrono::nanoseconds d) { return std::chrono::duration<double>(d).count(); }

/// An arrival time as the limiter's time (it looks only at differences): the limiter follows the
/// messages' own times, which the tests feed.
LogLimit::Clock::time_point log_time(UtcNs arrival) {
  return LogLimit::Clock::time_point{
      std::chrono::duration_cast<LogLimit::Clock::duration>(arrival.time_since_epoch())};
}

/// The start of a refused message for the log: printable, at most 48 characters.
std::string excerpt(std::string_view bytes) {
  std::string out;
  for (const char ch : bytes.substr(0, 48)) {
    const auto c = static_cast<unsigned char>(ch);
    out += std::isprint(c) ? std::string(1, ch) : fmt::format("\\x{:02x}", c);
  }
  if (bytes.size() > 48) out += fmt::format("... ({} bytes)", bytes.size());
  return out;
}

}  // namespace

std::uint64_t SocketSourceStats::rejected_total() const {
  std::uint64_t n = 0;
  for (const auto r : rejected) n += r;
  return n;
}

SocketPoseSource::SocketPoseSource(std::unique_ptr<transport::PoseSocket> socket, const LocalFrame& frame,
                                   const SocketSourceOptions& options)
    : socket_(std::move(socket)), frame_(frame), options_(options), history_(options.history) {
  spdlog::info("waiting for poses on {}", socket_->describe());
}

SocketPoseSource::~SocketPoseSource() {
  std::string reasons;
  for (std::size_t i = 0; i < kPoseRejectCount; ++i) {
    if (stats_.rejected[i] == 0) continue;
    reasons += fmt::format("{}{} {}", reasons.empty() ? "" : ", ", to_string(static_cast<PoseReject>(i)),
                           stats_.rejected[i]);
  }
  const std::string connections =
      stats_.connections == 0 ? std::string()
                              : fmt::format("; {} connections, {} closed by the sender, {} closed idle, {} taken over",
                                            stats_.connections, stats_.disconnections, stats_.idle_closed,
                                            stats_.taken_over);
  spdlog::info("pose input {}: {} poses used, {} dropped{}{}; {} sender changes, {} restarts{}", socket_->describe(),
               stats_.accepted, stats_.rejected_total(), reasons.empty() ? "" : " by reason: ", reasons,
               stats_.sender_changes, stats_.restarts, connections);
}

std::string SocketPoseSource::describe() const {
  if (options_.sender_time_base) {
    return fmt::format("{} (JSON poses with 't', lockstep: t = 0 is {}; no fix after {} s of sim time without "
                       "one, extrapolation up to {} s)", socket_->describe(),
                       format_iso8601_utc(*options_.sender_time_base), seconds(options_.history.timeout),
                       seconds(options_.history.horizon));
  }
  return fmt::format("{} (JSON poses; no fix after {} s without one, extrapolation up to {} s)",
                     socket_->describe(), seconds(options_.history.timeout), seconds(options_.history.horizon));
}

std::optional<UtcNs> SocketPoseSource::sim_time() const {
  if (!options_.sender_time_base || history_.empty()) return std::nullopt;
  return history_.newest().time;
}

void SocketPoseSource::service() {
  for (std::size_t i = 0; i < options_.max_messages_per_service; ++i) {
    const auto m = socket_->receive();
    if (!m) return;
    handle_message(*m);
  }
}

void SocketPoseSource::reject(PoseReject reason, const transport::ReceivedMessage& m, std::uint64_t count) {
  const auto i = static_cast<std::size_t>(reason);
  stats_.rejected[i] += count;
  unreported_[i] += count;
  if (!reject_log_[i].admit(log_time(m.arrival))) return;
  (void)reject_log_[i].take_suppressed();  // the line counts the messages themselves
  const bool show_bytes = reason != PoseReject::too_large && reason != PoseReject::kernel_overflow &&
                          reason != PoseReject::too_many_clients && !m.bytes.empty();
  spdlog::warn("pose input: dropped {} from {}: {} ({} in all){}", unreported_[i] == 1 ? "a message" :
               fmt::format("{} messages", unreported_[i]), m.sender_name.empty() ? "?" : m.sender_name,
               to_string(reason), stats_.rejected[i], show_bytes ? fmt::format(": '{}'", excerpt(m.bytes)) : "");
  unreported_[i] = 0;
}

void SocketPoseSource::note_connection(const transport::ReceivedMessage& m, std::uint64_t& total) {
  using Kind = transport::ReceivedMessage::Kind;
  ++total;
  const auto i = static_cast<std::size_t>(m.kind);
  ++unnoted_[i];
  if (!note_log_[i].admit(log_time(m.arrival))) return;
  (void)note_log_[i].take_suppressed();  // the line counts the connections themselves
  const char* what = m.kind == Kind::connected      ? "connected"
                     : m.kind == Kind::disconnected ? "disconnected"
                     : m.kind == Kind::idle_closed  ? "closed: no complete line within the idle timeout"
                                                    : "closed to make room for a new connection (idle)";
  if (unnoted_[i] == 1) {
    spdlog::info("pose sender {} {} ({} in all)", m.sender_name, what, total);
  } else {
    spdlog::info("pose sender {} {}, and {} more since the last such line ({} in all)", m.sender_name, what,
                 unnoted_[i] - 1, total);
  }
  unnoted_[i] = 0;
}

Enu SocketPoseSource::to_local(const PoseMessage& pose) const {
  if (const auto* enu = std::get_if<Enu>(&pose.position)) return *enu;
  const auto& g = std::get<GeodeticPose>(pose.position);
  return frame_.to_enu({g.lat_deg, g.lon_deg, g.alt_msl_m.value_or(frame_.origin().alt_m)});
}

void SocketPoseSource::handle_message(const transport::ReceivedMessage& m) {
  using Kind = transport::ReceivedMessage::Kind;
  switch (m.kind) {
    case Kind::too_large: return reject(PoseReject::too_large, m);
    case Kind::partial_line: return reject(PoseReject::partial_line, m);
    case Kind::kernel_dropped: return reject(PoseReject::kernel_overflow, m, m.count);
    case Kind::refused_client: return reject(PoseReject::too_many_clients, m);
    case Kind::connected: return note_connection(m, stats_.connections);
    case Kind::disconnected:
    case Kind::idle_closed:
    case Kind::taken_over:
      note_connection(m, m.kind == Kind::disconnected ? stats_.disconnections
                         : m.kind == Kind::idle_closed ? stats_.idle_closed
                                                       : stats_.taken_over);
      if (owner_ == m.sender) owner_.reset();  // the next sender may take over at once
      return;
    case Kind::message: break;
  }

  const PoseDecodeResult decoded = decode_pose(m.bytes);
  if (const auto* why = std::get_if<PoseReject>(&decoded)) return reject(*why, m);
  const auto& pose = std::get<PoseMessage>(decoded);
  // Lockstep: the sender's time is the time base, so a pose without one cannot be placed.
  if (options_.sender_time_base && !pose.sender_time_s) return reject(PoseReject::missing_key, m);

  if (owner_ != m.sender) {
    if (owner_ && m.arrival - owner_last_ <= options_.history.timeout) return reject(PoseReject::other_sender, m);
    if (owner_ || !owner_name_.empty()) {
      ++stats_.sender_changes;
      spdlog::info("pose sender is now {} (was {})", m.sender_name, owner_name_);
    } else {
      spdlog::info("first pose from {}", m.sender_name);
    }
    history_.clear();
    sender_clock_.reset();
    owner_ = m.sender;
    owner_name_.assign(m.sender_name);
  }

  const UtcNs time = options_.sender_time_base
                         ? *options_.sender_time_base +
                               std::chrono::nanoseconds{std::llround(*pose.sender_time_s * 1e9)}
                     : pose.sender_time_s ? sender_clock_.place(m.arrival, *pose.sender_time_s)
                                          : m.arrival;
  const TimedPose timed{time, pose.sender_time_s, to_local(pose), pose.velocity_mps, pose.yaw_deg,
                        Tilt{pose.pitch_deg, pose.roll_deg}};
  const PushResult pushed = history_.push(timed);
  if (const auto why = refusal_of(pushed)) return reject(*why, m);
  if (pushed == PushResult::restarted) {
    sender_clock_.reset();
    ++stats_.restarts;
    spdlog::warn("pose input: sender time or clock went back (simulator restarted?): pose history cleared");
  }
  ++stats_.accepted;
  owner_last_ = m.arrival;
}

std::optional<Truth> SocketPoseSource::truth_at(UtcNs t) {
  std::optional<Truth> truth = history_.sample(t);
  transitions_.note(truth.has_value(), t, history_, owner_name_);
  return truth;
}

std::unique_ptr<PoseSource> make_socket_source(bool udp, const transport::PoseEndpoint& endpoint,
                                               const LocalFrame& frame, const SocketSourceOptions& options) {
  const transport::PoseSocketOptions socket_options{.max_message_bytes = kMaxPoseMessageBytes, .max_clients = 8};
  std::unique_ptr<transport::PoseSocket> socket = udp ? transport::open_udp_pose_socket(endpoint, socket_options)
                                                                  : transport::open_tcp_pose_server(endpoint, socket_options);
  return std::make_unique<SocketPoseSource>(std::move(socket), frame, options);
}

}  // namespace gpsemu::sources
