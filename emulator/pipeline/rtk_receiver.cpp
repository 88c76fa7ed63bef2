// The RTK part of a receiver channel (see rtk_receiver.hpp).
#include "emulator/pipeline/rtk_receiver.hpp"

#include <algorithm>

#include <GeographicLib/Geocentric.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/model/accuracy.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/model/receiver_models.hpp"

namespace gpsemu {
namespace {

constexpr int kReadsPerService = 64;

int rank(nmea::FixQuality q) {
  switch (q) {
    case nmea::FixQuality::rtk_fixed: return 3;
    case nmea::FixQuality::rtk_float: return 2;
    case nmea::FixQuality::dgps: return 1;
    default: return 0;
  }
}

std::string_view state_name(nmea::FixQuality q) {
  switch (q) {
    case nmea::FixQuality::rtk_fixed: return "RTK fixed";
    case nmea::FixQuality::rtk_float: return "RTK float";
    case nmea::FixQuality::dgps: return "DGPS";
    default: return "no corrections (3-D)";
  }
}

}  // namespace

RtkReceiver::RtkReceiver(const rtk::RtkTimeline& timeline, const std::optional<transport::RtcmInputSpec>& rtcm)
    : state_(timeline) {
  if (rtcm) {
    socket_ = transport::open_rtcm_socket(*rtcm);
    spdlog::info("RTK: reading RTCM3 corrections on {}", socket_->describe());
  }
}

RtkReceiver::RtkReceiver(const rtk::RtkTimeline& timeline, std::unique_ptr<transport::RtcmSocket> socket)
    : state_(timeline), socket_(std::move(socket)) {}

void RtkReceiver::received(const rtk::Rtcm3Message& m) {
  ++counts_.messages;
  if (!m.valid) ++counts_.invalid;
  if (counts_.by_type[m.type & 0xFFFu]++ == 0) {
    spdlog::info("RTK: first RTCM3 {}{}{}", rtk::describe(m), m.station_id ? fmt::format(" from station {}", *m.station_id) : "",
                 m.valid ? "" : " (shorter than its type requires: not used)");
  }
  state_.received(m);
}

std::size_t RtkReceiver::service() {
  if (!socket_) return 0;
  std::size_t reads = 0;
  for (int i = 0; i < kReadsPerService; ++i) {
    const std::optional<transport::RtcmBytes> got = socket_->receive();
    if (!got) break;
    ++reads;
    auto it = std::find_if(streams_.begin(), streams_.end(), [&](const Stream& s) { return s.source == got->source; });
    if (got->closed) {
      if (it != streams_.end()) streams_.erase(it);
      continue;
    }
    if (it == streams_.end()) {
      if (streams_.size() >= kMaxStreams) streams_.erase(streams_.begin());
      streams_.push_back(Stream{got->source, {}});
      it = streams_.end() - 1;
    }
    const std::uint64_t bad_before = it->reader.stats().bad_crc, garbage_before = it->reader.stats().garbage_bytes;
    for (const rtk::Rtcm3Frame& frame : it->reader.feed(got->bytes)) {
      socket_->frame_from(got->source);  // a good CRC: this stream is a base station's
      received(rtk::decode_rtcm3(frame.payload));
    }
    counts_.stream_bad_crc += it->reader.stats().bad_crc - bad_before;
    counts_.stream_garbage_bytes += it->reader.stats().garbage_bytes - garbage_before;
  }
  const transport::RtcmSocket::Drops drops = socket_->drops();
  if ((drops.refused != drops_logged_.refused || drops.replaced != drops_logged_.replaced ||
       drops.other_senders != drops_logged_.other_senders) &&
      log_limited(drop_log_, spdlog::level::warn,
                             "RTK: {}: {} connection(s) refused (every slot held by a base), {} closed to make room "
                             "(no good frame, or quiet {} s), {} datagram(s) of other senders dropped (so far)",
                             socket_->describe(), drops.refused, drops.replaced, transport::RtcmSocket::kQuietS,
                             drops.other_senders)) {
    drops_logged_ = drops;
  }
  if (counts_.stream_bad_crc != bad_crc_logged_ && bad_crc_log_.admit(LogLimit::Clock::now())) {
    (void)bad_crc_log_.take_suppressed();
    spdlog::warn("RTK: {} RTCM3 frame(s) with a bad CRC dropped on {} ({} in all)", counts_.stream_bad_crc - bad_crc_logged_,
                 socket_->describe(), counts_.stream_bad_crc);
    bad_crc_logged_ = counts_.stream_bad_crc;
  }
  return reads;
}

void RtkReceiver::apply(UtcNs t, nmea::Fix& fix, const std::optional<Enu>& truth_m, const LocalFrame& frame) {
  // No correction ever: nothing to do (the receiver's ECEF position costs ~100 ns an epoch).
  if (counts_.messages == 0) return;
  std::optional<std::array<double, 3>> rover;
  if (fix.has_fix()) {
    std::array<double, 3> ecef{};
    GeographicLib::Geocentric::WGS84().Forward(fix.lat_deg, fix.lon_deg, fix.alt_msl_m + fix.geoid_sep_m, ecef[0], ecef[1],
                                               ecef[2]);
    rover = ecef;
  }
  const double t_s = std::chrono::duration<double>(t.time_since_epoch()).count();
  const rtk::RtkStatus s = state_.step(t_s, rover);
  status_ = s;
  if (!fix.has_fix()) return;
  if (logged_ != s.quality) {
    if (logged_ || s.differential()) {
      std::string detail;
      if (s.baseline_m) detail = fmt::format("baseline {:.0f} m", *s.baseline_m);
      if (s.correction_age_s) detail += fmt::format("{}correction age {:.1f} s", detail.empty() ? "" : ", ", *s.correction_age_s);
      spdlog::info("RTK: {}{}", state_name(s.quality), detail.empty() ? std::string{} : " (" + detail + ")");
    }
    logged_ = s.quality;
  }
  if (!s.differential()) return;
  fix.diff_age_s = s.correction_age_s;
  if (s.station_id) fix.diff_station_id = *s.station_id;
  if (rank(s.quality) <= rank(fix.quality)) return;  // the configured quality is as good: kept
  const double k = noise_scale(s.quality) / noise_scale(fix.quality);
  if (truth_m) {
    const Enu reported = frame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m});
    const Geodetic p = frame.to_geodetic(*truth_m + k * (reported - *truth_m));
    fix.lat_deg = p.lat_deg;
    fix.lon_deg = p.lon_deg;
    fix.alt_msl_m = p.alt_m;
  }
  fix.sigma_lat_m *= k;
  fix.sigma_lon_m *= k;
  fix.sigma_alt_m *= k;
  fix.range_rms_m *= k;
  fix.quality = s.quality;
  sky::apply_accuracy_floor(fix);
  ++(s.quality == nmea::FixQuality::rtk_fixed   ? counts_.epochs_fixed
     : s.quality == nmea::FixQuality::rtk_float ? counts_.epochs_float
                                                : counts_.epochs_dgps);
}

std::string RtkReceiver::summary(std::uint64_t port_bad_crc) const {
  const std::uint64_t bad = port_bad_crc + counts_.stream_bad_crc;
  if (counts_.messages == 0 && bad == 0) return {};
  std::string types;
  for (std::size_t type = 0; type < counts_.by_type.size(); ++type) {
    if (counts_.by_type[type] == 0) continue;
    types += fmt::format("{}{} x{}", types.empty() ? "" : ", ", type, counts_.by_type[type]);
  }
  std::string input;
  if (socket_) {
    const transport::RtcmSocket::Drops d = socket_->drops();
    input = fmt::format("; {}: {} connection(s) refused, {} closed to make room, {} datagram(s) of other senders dropped",
                        socket_->describe(), d.refused, d.replaced, d.other_senders);
  }
  return fmt::format("RTK: {} RTCM3 message(s) ({}), {} bad CRC dropped, {} too short; epochs DGPS {}, float {}, fixed {}{}",
                     counts_.messages, types.empty() ? "none" : types, bad, counts_.invalid, counts_.epochs_dgps,
                     counts_.epochs_float, counts_.epochs_fixed, input);
}

}  // namespace gpsemu
