// libFuzzer target for RTCM3 input (emulator/rtk, and the u-blox port that splits it from UBX):
// arbitrary bytes, in chunks the first byte picks, through
//  - rtk::Rtcm3Reader: it returns exactly stats().frames_ok frames, each at most 1023 bytes, each
//    framed again to the same bytes that read back as itself; counts by type add up;
//  - rtk::decode_rtcm3 of every frame and of the raw input: MSM counts within their masks' sizes;
//  - rtk::RtkState fed with them and stepped a second per chunk: only the four qualities, a
//    correction age >= 0 exactly while differential; the NAV-RELPOSNED of a fixed base's rover
//    from it (whatever base position arrived) is 64 bytes, valid only when differential, finite;
//  - a ubx::Session on an F9P with RXM-RTCM on: every reply is whole UBX frames, the RTCM3 frames
//    the reader counted are the messages take_rtcm() returns and those the port's input protocols
//    set aside (a CFG message in the input may turn RTCM3 off), none dropped below its bound.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "emulator/rtk/rtk_state.hpp"
#include "emulator/rtk/static_base_relpos.hpp"
#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/session.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using namespace gpsemu;

void check_message(const rtk::Rtcm3Message& m) {
  if (!m.msm) return;
  GPSEMU_FUZZ_CHECK(m.msm->satellites >= 0 && m.msm->satellites <= 64);
  GPSEMU_FUZZ_CHECK(m.msm->signals >= 0 && m.msm->signals <= 32);
  GPSEMU_FUZZ_CHECK(!m.valid || m.msm->cells <= 64);
  GPSEMU_FUZZ_CHECK(m.msm->msm >= 1 && m.msm->msm <= 7);
}

void check_whole_ubx_frames(std::string_view bytes) {
  std::size_t at = 0;
  while (at < bytes.size()) {
    GPSEMU_FUZZ_CHECK(at + ubx::frame_overhead_bytes <= bytes.size());
    GPSEMU_FUZZ_CHECK(static_cast<std::uint8_t>(bytes[at]) == ubx::sync1);
    const std::size_t length = ubx::get_u2(bytes, at + 4);
    GPSEMU_FUZZ_CHECK(at + ubx::frame_overhead_bytes + length <= bytes.size());
    GPSEMU_FUZZ_CHECK(ubx::get_u2(bytes, at + 6 + length) == ubx::fletcher_checksum(bytes.substr(at + 2, 4 + length)));
    at += ubx::frame_overhead_bytes + length;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 64;
  const std::string_view input(reinterpret_cast<const char*>(data) + 1, size - 1);

  check_message(rtk::decode_rtcm3(input));

  rtk::Rtcm3Reader reader;
  rtk::RtkState rtk;
  std::uint64_t frames = 0;
  double t_s = 0.0;
  for (std::size_t at = 0; at < input.size(); at += chunk) {
    for (const rtk::Rtcm3Frame& f : reader.feed(input.substr(at, chunk))) {
      ++frames;
      GPSEMU_FUZZ_CHECK(f.payload.size() <= rtk::rtcm3_max_payload_bytes);
      rtk::Rtcm3Reader again;
      const auto back = again.feed(rtk::rtcm3_frame_bytes(f.payload));
      GPSEMU_FUZZ_CHECK(back.size() == 1 && back[0] == f);
      const rtk::Rtcm3Message m = rtk::decode_rtcm3(f.payload);
      GPSEMU_FUZZ_CHECK(m.type == f.message_type());
      check_message(m);
      rtk.received(m);
    }
    t_s += 1.0;
    const rtk::RtkStatus s = rtk.step(t_s, std::array<double, 3>{4198944.0, 174747.0, 4781886.0});
    using Q = nmea::FixQuality;
    GPSEMU_FUZZ_CHECK(s.quality == Q::gps || s.quality == Q::dgps || s.quality == Q::rtk_float || s.quality == Q::rtk_fixed);
    GPSEMU_FUZZ_CHECK(s.correction_age_s.has_value() == s.differential());
    GPSEMU_FUZZ_CHECK(!s.correction_age_s || *s.correction_age_s >= 0.0);
    nmea::Fix fix;
    fix.quality = s.quality;
    fix.lat_deg = 48.8;
    fix.lon_deg = 2.3;
    fix.sigma_lat_m = fix.sigma_lon_m = fix.sigma_alt_m = 0.01;
    const RelativePosition rel = rtk::static_base_relpos(s, rtk.base(), fix);
    GPSEMU_FUZZ_CHECK(!rel.rel_pos_valid || (rel.diff_soln && rtk.base()));
    GPSEMU_FUZZ_CHECK(!rel.rel_pos_valid || (std::isfinite(rel.length_m) && rel.length_m >= 0.0));
    GPSEMU_FUZZ_CHECK(ubx::nav_relposned(fix, rel).size() == 64);
  }
  GPSEMU_FUZZ_CHECK(frames == reader.stats().frames_ok);
  std::uint64_t by_type = 0;
  for (const std::uint64_t n : reader.stats().by_type) by_type += n;
  GPSEMU_FUZZ_CHECK(by_type == frames);

  ubx::SessionSettings settings;
  settings.start.model = ReceiverModel::ublox_f9p;
  ubx::Session session(settings);
  session.client_wrote(ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x02\x32\x01", 3)));
  check_whole_ubx_frames(session.take_reply());
  std::uint64_t taken = 0;
  for (std::size_t at = 0; at < input.size(); at += chunk) {
    session.client_wrote(input.substr(at, chunk));
    check_whole_ubx_frames(session.take_reply());
    const auto messages = session.take_rtcm();
    GPSEMU_FUZZ_CHECK(messages.size() <= ubx::Session::max_pending_rtcm);
    taken += messages.size();
  }
  GPSEMU_FUZZ_CHECK(session.stats().rtcm_not_taken == 0);
  GPSEMU_FUZZ_CHECK(taken + session.stats().rtcm_ignored == session.reader_stats().rtcm_ok);
  return 0;
}
