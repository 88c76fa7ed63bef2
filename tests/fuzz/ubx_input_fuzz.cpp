// libFuzzer target for emulator/ubx: arbitrary client bytes (UBX frames, PUBX commands, garbage)
// through the configuration state machine of a model the first byte picks, in chunks the second
// byte picks; then NAV messages of a fix made from the same bytes. Traps when an invariant breaks:
//  - every answer is a sequence of whole, checksummed UBX frames, and the reader returns exactly
//    stats().frames_ok frames;
//  - the settings stay valid: a measurement period a u-blox accepts, a 36-byte CFG-NAV5, a
//    CFG-GNSS of whole blocks, an 8-byte CFG-SBAS, a supported baud on the client's port;
//  - every NAV payload has its message's length;
//  - driven as the epoch loop drives a u-blox port (ubx::Session: client bytes in chunks, the
//    reply taken after each, now and then an epoch that applies the waiting effects and writes a
//    solution): the queues stay bounded whatever the client writes (one waiting poll a NAV kind,
//    at most one effect of each of the three kinds), every count adds up (waiting + folded =
//    polled), every reply and epoch is whole frames and sentences, and a solution answers every
//    waiting poll.
//  - a session's clients (each chunk from the client a byte picks, which may leave first) each get
//    whole frames only, never more than Session::max_reply_bytes at once, whatever the others wrote.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_legacy.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/messages.hpp"
#include "emulator/ubx/nav.hpp"
#include "emulator/ubx/model.hpp"
#include "emulator/ubx/output.hpp"
#include "emulator/ubx/session.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using namespace gpsemu;
using namespace gpsemu::ubx;

void check_answer(std::string_view bytes) {
  std::size_t at = 0;
  while (at < bytes.size()) {
    GPSEMU_FUZZ_CHECK(bytes.size() - at >= frame_overhead_bytes);
    GPSEMU_FUZZ_CHECK(get_u1(bytes, at) == sync1 && get_u1(bytes, at + 1) == sync2);
    const std::size_t length = get_u2(bytes, at + 4);
    GPSEMU_FUZZ_CHECK(at + frame_overhead_bytes + length <= bytes.size());
    GPSEMU_FUZZ_CHECK(get_u2(bytes, at + 6 + length) == fletcher_checksum(bytes.substr(at + 2, 4 + length)));
    at += frame_overhead_bytes + length;
  }
}

void check_settings(const ConfigMachine& machine) {
  const Settings& s = machine.settings();
  GPSEMU_FUZZ_CHECK(s.meas_period_ms >= min_meas_period_ms && s.nav_rate_cycles >= 1);
  GPSEMU_FUZZ_CHECK(s.nav5.size() == 36);
  GPSEMU_FUZZ_CHECK(s.gnss.size() == 4 + 8 * static_cast<std::size_t>(get_u1(s.gnss, 3)));
  GPSEMU_FUZZ_CHECK(s.sbas.size() == 8);
  GPSEMU_FUZZ_CHECK(is_supported_baud(s.ports[static_cast<std::size_t>(Port::uart1)].baud));
}

void fuzz_machine(std::string_view input) {
  if (input.size() < 2) return;
  StartSettings start;
  start.model = static_cast<ReceiverModel>(static_cast<unsigned char>(input[0]) % 4);
  const std::size_t chunk = 1 + static_cast<unsigned char>(input[1]) % 61;
  input.remove_prefix(2);
  ConfigMachine machine(start);
  for (std::size_t begin = 0; begin < input.size(); begin += chunk) {
    const Answer answer = machine.feed(input.substr(begin, chunk));
    check_answer(answer.bytes);
    check_settings(machine);
  }
  FrameReader reader;
  std::uint64_t frames = 0;
  for (const ClientMessage& m : reader.feed(input)) frames += std::holds_alternative<Frame>(m) ? 1 : 0;
  GPSEMU_FUZZ_CHECK(frames == reader.stats().frames_ok);
}

/// Every byte of `bytes` belongs to a whole, checksummed UBX frame or a valid NMEA sentence.
void check_whole(std::string_view bytes) {
  FrameReader reader;
  (void)reader.feed(bytes);
  const FrameStats& s = reader.stats();
  GPSEMU_FUZZ_CHECK(s.bad_checksum == 0 && s.too_long == 0 && s.bad_sentences == 0);
  GPSEMU_FUZZ_CHECK(s.garbage_bytes <= 2 * s.sentences_ok);  // only the sentences' CR LF
}

/// The client's bytes through a Session as the loop drives it: a chunk, its reply, and when the
/// third input byte's bits say so, an epoch (effects taken, a solution written) 100 ms later.
void fuzz_session(std::string_view input) {
  if (input.size() < 3) return;
  SessionSettings settings;
  settings.start.model = static_cast<ReceiverModel>(static_cast<unsigned char>(input[0]) % 4);
  settings.start.measurement_period = std::chrono::milliseconds{100};
  const std::size_t chunk = 1 + static_cast<unsigned char>(input[1]) % 61;
  const unsigned epochs_mask = static_cast<unsigned char>(input[2]);
  input.remove_prefix(3);
  Session session(settings);
  nmea::Fix fix;
  fix.time_utc = nmea::UtcTime{std::chrono::hours{24 * 20000 + 12}};
  fix.quality = nmea::FixQuality::gps;
  fix.lat_deg = 47.0;
  fix.lon_deg = 8.0;
  FrameReader polls_seen;  // counts the NAV polls the client wrote, as the session's reader does
  std::uint64_t nav_polls = 0;
  std::uint64_t polls_answered = 0;
  std::uint64_t effects_taken = 0;
  std::size_t turn = 0;
  for (std::size_t begin = 0; begin < input.size(); begin += chunk, ++turn) {
    const std::string_view piece = input.substr(begin, chunk);
    session.client_wrote(piece);
    for (const ClientMessage& m : polls_seen.feed(piece)) {
      const auto* f = std::get_if<Frame>(&m);
      // As the machine answers them: a NAV or MON poll of a message the model has waits for the
      // next solution (one it lacks gets nothing).
      nav_polls += f && (f->id.msg_class == 0x01 || f->id.msg_class == 0x0A) && f->payload.empty() &&
                           solution_encodes(f->id) && model_has_message(settings.start.model, f->id)
                       ? 1
                       : 0;
    }
    check_answer(session.take_reply());
    GPSEMU_FUZZ_CHECK(session.polls_waiting() <= 16);
    GPSEMU_FUZZ_CHECK(session.effects_waiting() <= 3);
    if (((epochs_mask >> (turn % 8)) & 1) == 0) continue;
    // An epoch: the loop takes the effects, then the receiver writes its solution.
    const std::vector<Effect> effects = session.take_effects();
    GPSEMU_FUZZ_CHECK(effects.size() <= 3);
    for (std::size_t a = 0; a < effects.size(); ++a) {
      for (std::size_t b = a + 1; b < effects.size(); ++b) GPSEMU_FUZZ_CHECK(effects[a].index() != effects[b].index());
    }
    effects_taken += effects.size();
    const std::size_t waiting = session.polls_waiting();
    std::string out;
    const bool on_grid = session.on_solution_grid(fix.time_utc);
    session.append_solution(epoch_of(fix), out);
    check_whole(out);
    if (on_grid) {
      GPSEMU_FUZZ_CHECK(session.polls_waiting() == 0);
      polls_answered += waiting;
    }
    fix.time_utc += std::chrono::milliseconds{100};
  }
  GPSEMU_FUZZ_CHECK(polls_answered + session.polls_waiting() + session.stats().polls_merged == nav_polls);
  (void)effects_taken;
}

/// Several clients of one session, leaving and writing in turn.
void fuzz_clients(std::string_view input) {
  if (input.size() < 2) return;
  SessionSettings settings;
  settings.start.model = static_cast<ReceiverModel>(static_cast<unsigned char>(input[0]) % 4);
  const std::size_t chunk = 1 + static_cast<unsigned char>(input[1]) % 61;
  input.remove_prefix(2);
  Session session(settings);
  for (std::size_t begin = 0; begin < input.size(); begin += chunk) {
    // The chunk's first byte picks its client (one of 4) and whether that client left before it.
    const auto pick = static_cast<unsigned char>(input[begin]);
    const ClientId client = pick % 4;
    if ((pick & 0x80) != 0) session.client_left(client);
    session.client_wrote(input.substr(begin, chunk), client);
    const std::string reply = session.take_reply(client);
    GPSEMU_FUZZ_CHECK(reply.size() <= Session::max_reply_bytes);
    check_answer(reply);
    check_settings(session.machine());
  }
}

template <class T>
T take(std::string_view& input) {
  T value{};
  if (input.size() >= sizeof(T)) {
    std::memcpy(&value, input.data(), sizeof(T));
    input.remove_prefix(sizeof(T));
  }
  return value;
}

void fuzz_nav(std::string_view input) {
  nmea::Fix fix;
  fix.time_utc = nmea::UtcTime{std::chrono::milliseconds{take<std::int64_t>(input) % 4'000'000'000'000}};
  fix.quality = static_cast<nmea::FixQuality>(take<std::uint8_t>(input) % 7);
  fix.dimension = static_cast<nmea::FixDimension>(1 + take<std::uint8_t>(input) % 3);
  fix.lat_deg = take<double>(input);
  fix.lon_deg = take<double>(input);
  fix.alt_msl_m = take<double>(input);
  fix.speed_mps = take<double>(input);
  fix.course_deg_true = take<double>(input);
  fix.sigma_lat_m = take<double>(input);
  fix.pdop = take<double>(input);
  fix.satellites_used = take<std::int8_t>(input);
  fix.satellites_in_view = take<std::int8_t>(input);
  for (auto& sat : fix.satellites) {
    sat.prn = take<std::uint8_t>(input);
    sat.sv_id = take<std::uint8_t>(input);
    sat.system = static_cast<nmea::GnssSystem>(take<std::uint8_t>(input) % 7);
    if (take<std::uint8_t>(input) % 2 == 0) sat.snr_dbhz = take<std::uint8_t>(input);
  }
  NavExtras extras;
  fix.sigma_speed_mps = take<double>(input);
  const std::pair<MessageId, std::size_t> sizes[] = {{msg::nav_pvt, 92},    {msg::nav_posllh, 28}, {msg::nav_velned, 36},
                                                     {msg::nav_status, 16}, {msg::nav_sol, 52},    {msg::nav_dop, 18},
                                                     {msg::nav_timeutc, 20}, {msg::nav_timegps, 16}, {msg::nav_cov, 64},
                                                     {msg::nav_clock, 20},   {msg::nav_hpposllh, 36}};
  for (const auto& [id, bytes] : sizes) GPSEMU_FUZZ_CHECK(solution_payload(id, fix, extras)->size() == bytes);
  const std::size_t sats = nav_sat(fix).size();
  GPSEMU_FUZZ_CHECK(sats >= 8 && (sats - 8) % 12 == 0 && sats <= 8 + 12 * nmea::max_satellites);
  GPSEMU_FUZZ_CHECK(nav_svinfo(fix).size() == sats);
  const std::size_t sigs = nav_sig(fix, ReceiverModel::ublox_f9p).size();
  GPSEMU_FUZZ_CHECK(sigs >= 8 && (sigs - 8) % 16 == 0 && sigs <= 8 + 2 * 16 * nmea::max_satellites);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  fuzz_machine(input);
  fuzz_session(input);
  fuzz_clients(input);
  fuzz_nav(input);
  return 0;
}
