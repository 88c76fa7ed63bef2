// The RTK options of the option table (docs/rtk.md): the base station's RTCM3 input and the RTK
// state timeline. Kept apart from config_options.cpp (its size).
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/config/config_options.hpp"
#include "emulator/config/config_values.hpp"
#include "emulator/rtk/rtk_state.hpp"

namespace gpsemu {

void add_rtk_options(std::vector<OptionDef>& t) {
  using V = const std::vector<std::string>&;
  using namespace config_values;
  const auto add = [&t](std::string name, std::string value_name, std::string help,
                        std::function<void(ConfigDraft&, V)> apply) {
    t.push_back({std::move(name), std::move(value_name), std::move(help), OptionScope::receiver, false, std::move(apply)});
  };
  add("rtcm", "SPEC", "RTCM3 corrections from a base station: tcp:[HOST:]PORT (str2str or an NTRIP client connects) | "
      "udp:[HOST:]PORT; RTCM3 written to a u-blox port is read as well (docs/rtk.md) (default none)",
      [](ConfigDraft& d, V v) { d.receiver.settings.rtcm = transport::parse_rtcm_input_spec(v.back()); });
  add("rtk-convergence", "FLOAT,FIX[,PER_KM]", "RTK timeline from the first correction (MSM) of a base whose "
      "position is known: seconds to RTK float, seconds to RTK fixed at a zero baseline, seconds added to it per km "
      "of baseline, each 0..3600 (default 3,10,2)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("rtk-convergence", v.back(), 2, 3);
        for (const double s : x) {
          if (s < 0.0 || s > 3600.0) throw std::invalid_argument(fmt::format("rtk-convergence: seconds must be 0..3600, got '{}'", v.back()));
        }
        rtk::RtkTimeline& r = d.receiver.settings.rtk;
        r.float_after_s = x[0];
        r.fix_base_s = x[1];
        if (x.size() > 2) r.fix_per_km_s = x[2];
        rtk::validate(r);
      });
  add("rtk-timeouts", "FIXED,FLOAT,DGPS", "correction age, seconds, above which RTK fixed falls to float, float to "
      "DGPS, and DGPS to an autonomous fix (the F9P's DGNSS timeout), increasing, 0.1..3600 (default 5,30,60)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("rtk-timeouts", v.back(), 3, 3);
        for (const double s : x) {
          if (s < 0.1 || s > 3600.0) throw std::invalid_argument(fmt::format("rtk-timeouts: seconds must be 0.1..3600, got '{}'", v.back()));
        }
        rtk::RtkTimeline& r = d.receiver.settings.rtk;
        r.fixed_max_age_s = x[0];
        r.float_max_age_s = x[1];
        r.dgps_max_age_s = x[2];
        rtk::validate(r);
      });
  add("rtk-max-baseline", "KM", "beyond this distance to the base, corrections give DGPS only, 0.1..1000 km "
      "(default 50)",
      [](ConfigDraft& d, V v) { d.receiver.settings.rtk.max_baseline_km = parse_number("rtk-max-baseline", v.back(), 0.1, 1000.0); });
}

}  // namespace gpsemu
