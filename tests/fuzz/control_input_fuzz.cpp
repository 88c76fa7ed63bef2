// libFuzzer target for the control socket's protocol (faults/control.hpp): each '\n'-separated
// line of the input through FaultControl over two receivers' fault timelines, with an epoch of a
// fix through both after each line (the truth moving, so `where` areas are entered and left).
// Checks: nothing crashes or throws, every answer is one JSON object with a class, an ERROR has a
// message, every fix stays finite, and every applied event's --tee line reads back as a scenario
// (faults/tee_events.hpp) without an error.
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "emulator/faults/control.hpp"
#include "emulator/faults/tee_events.hpp"

namespace {

using namespace gpsemu;

void check(bool ok) {
  if (!ok) std::abort();
}

nmea::Fix a_fix(const LocalFrame& frame, UtcNs t) {
  nmea::Fix fix;
  fix.time_utc = std::chrono::floor<std::chrono::milliseconds>(t);
  fix.quality = nmea::FixQuality::gps;
  fix.dimension = nmea::FixDimension::three_d;
  const Geodetic g = frame.to_geodetic({1.0, 2.0, 3.0});
  fix.lat_deg = g.lat_deg;
  fix.lon_deg = g.lon_deg;
  fix.alt_msl_m = g.alt_m;
  fix.satellites_in_view = 10;
  for (int i = 0; i < 10; ++i) {
    fix.satellites[static_cast<std::size_t>(i)].snr_dbhz = 25 + 2 * i;
    fix.satellites[static_cast<std::size_t>(i)].used = true;
  }
  fix.satellites_used = 10;
  fix.hdop = 1.0;
  fix.vdop = 1.5;
  fix.sigma_lat_m = fix.sigma_lon_m = fix.sigma_alt_m = 1.0;
  return fix;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const LocalFrame frame({47.0, 8.0, 400.0});
  static const bool quiet = [] {  // the start/end lines of every fault would drown the fuzzer's output
    spdlog::set_level(spdlog::level::off);
    return true;
  }();
  (void)quiet;
  const UtcNs start{};
  faults::FaultTimeline a({{}, ""}, start), b({{}, ""}, start);
  faults::FaultControl control({&a, &b});
  std::string_view input(reinterpret_cast<const char*>(data), size);
  int epoch = 0;
  while (!input.empty() && epoch < 200) {
    const std::size_t nl = input.find('\n');
    const std::string_view line = input.substr(0, nl);
    input.remove_prefix(nl == std::string_view::npos ? input.size() : nl + 1);
    const nlohmann::json answer = nlohmann::json::parse(control.handle(line), nullptr, false);
    check(!answer.is_discarded() && answer.is_object() && answer.contains("class"));
    if (answer["class"] == "ERROR") check(answer.contains("message") && answer["message"].is_string());
    ++epoch;
    for (faults::FaultTimeline* t : {&a, &b}) {
      const UtcNs now = start + std::chrono::milliseconds(100 * epoch);
      ReceiverEpoch built = epoch_of(a_fix(frame, now));
      const Enu truth{50.0 * epoch, 0.0, 0.0};
      (void)t->apply(now, built, truth, frame);
      const nmea::Fix& fix = built.fix;
      for (const faults::AppliedEvent& e : t->applied_events()) {
        try {
          (void)faults::faults_from_tee(faults::tee_event_line(e));
        } catch (const std::exception&) {
          check(false);  // what the control socket applied must replay
        }
      }
      check(std::isfinite(fix.lat_deg) && std::isfinite(fix.lon_deg) && std::isfinite(fix.alt_msl_m));
      check(std::isfinite(fix.hdop) && std::isfinite(fix.sigma_lat_m));
      check(fix.satellites_used >= 0 && fix.satellites_used <= fix.satellites_in_view);
    }
  }
  return 0;
}
