// libFuzzer target for emulator/ubx: arbitrary client bytes (UBX frames, PUBX commands, garbage)
// through the configuration state machine of a model the first byte picks, in chunks the second
// byte picks; then NAV messages of a fix made from the same bytes. Traps when an invariant breaks:
//  - every answer is a sequence of whole, checksummed UBX frames, and the reader returns exactly
//    stats().frames_ok frames;
//  - the settings stay valid: a measurement period a u-blox accepts, a 36-byte CFG-NAV5, a
//    CFG-GNSS of whole blocks, an 8-byte CFG-SBAS, a supported baud on the client's port;
//  - every NAV payload has its message's length.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_legacy.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/nav.hpp"
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
  extras.speed_sigma_mps = take<double>(input);
  const std::pair<MessageId, std::size_t> sizes[] = {{msg::nav_pvt, 92},    {msg::nav_posllh, 28}, {msg::nav_velned, 36},
                                                     {msg::nav_status, 16}, {msg::nav_sol, 52},    {msg::nav_dop, 18},
                                                     {msg::nav_timeutc, 20}, {msg::nav_timegps, 16}, {msg::nav_cov, 64},
                                                     {msg::nav_clock, 20},   {msg::nav_hpposllh, 36}};
  for (const auto& [id, bytes] : sizes) GPSEMU_FUZZ_CHECK(nav_payload(id, fix, extras)->size() == bytes);
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
  fuzz_nav(input);
  return 0;
}
