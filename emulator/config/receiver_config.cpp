#include "emulator/config/receiver_config.hpp"

#include <cmath>

#include "emulator/sources/make_source.hpp"

namespace gpsemu {

ReceiverOptions receiver_options(const ReceiverSettings& receiver) {
  ReceiverOptions options = receiver.model;
  options.noise_sigma_m = estimate_noise_sigma_m(receiver.noise, receiver.seed);
  options.sky_seed = receiver.seed;
  // A u-blox port may be asked for NAV-SAT, NAV-SVINFO or NAV-SIG at any time: it always has them.
  options.satellite_details = receiver.format.sentences.contains(nmea::SentenceType::gsa) ||
                              receiver.format.sentences.contains(nmea::SentenceType::gsv) ||
                              receiver.protocol != Protocol::nmea;
  return options;
}

std::unique_ptr<sources::PoseSource> make_receiver_source(const ReceiverSettings& receiver,
                                                          const TimelineSettings& timeline, const LocalFrame& frame,
                                                          UtcNs first_epoch) {
  sources::SocketSourceOptions socket;
  socket.history.timeout = std::chrono::nanoseconds{std::llround(receiver.pose_timeout_s * 1e9)};
  socket.history.horizon = std::chrono::nanoseconds{std::llround(receiver.pose_horizon_s * 1e9)};
  if (timeline.clock.kind == ClockKind::lockstep) socket.sender_time_base = timeline.start_time.value_or(first_epoch);
  return sources::make_source(receiver.source, receiver.sim, socket, frame, first_epoch);
}

nmea::LineBudget line_budget(const ReceiverSettings& receiver, double rate_hz) {
  const Geometry g = resolve_geometry(receiver_options(receiver));
  return nmea::line_budget(receiver.format, g.in_view_by_system, g.satellites_used, rate_hz);
}

}  // namespace gpsemu
