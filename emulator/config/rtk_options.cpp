// The RTK and heading options of the option table (docs/rtk.md, docs/heading.md): the base
// station's RTCM3 input, the RTK state timeline, the heading's noise and a moving-base pair's roles
// and antenna offsets. Kept apart from config_options.cpp (its size).
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/config/config_options.hpp"
#include "emulator/config/config_values.hpp"
#include "emulator/config/fleet_config.hpp"
#include "emulator/heading/moving_base.hpp"
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
      "udp:[HOST:]PORT; RTCM3 written to a u-blox port is read as well; in a fleet one port per receiver: "
      "{i} / {B+i} as in output, or each [[receiver]] table its own (docs/rtk.md) (default none)",
      [](ConfigDraft& d, V v) {
        // Checked now with receiver 0's port; each receiver's is opened from its own expansion.
        (void)transport::parse_rtcm_input_spec(expand_receiver_template("rtcm", v.back(), 0));
        d.receiver.rtcm = v.back();
      });
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
  add("heading-noise", "DEG", "1-sigma noise of the true heading (HDT, THS) from a pose's yaw_deg, 0..180 degrees "
      "(default 0.2, a dual-antenna receiver with a 1 m baseline)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.heading_sigma_deg = parse_number("heading-noise", v.back(), 0.0, 180.0); });
  add("role", "ROLE", "standalone | moving-base | rover: a moving-base pair on one vehicle in a fleet (docs/heading.md): "
      "the moving base also writes RTCM3 (4072.0, MSM4, 1230), the rover (--protocol ubx or nmea+ubx) reports "
      "NAV-RELPOSNED while it receives that RTCM3 (default standalone)",
      [](ConfigDraft& d, V v) { d.receiver.settings.moving_base.role = heading::parse_role(v.back()); });
  add("antenna-offset", "F,R,D", "the antenna's place on the vehicle, metres forward, right, down of the pose's point "
      "(body frame, each within +-100; with a pose's yaw_deg it moves the reported position and sets a moving-base "
      "pair's baseline) (default 0,0,0)",
      [](ConfigDraft& d, V v) { d.receiver.settings.moving_base.antenna = heading::parse_antenna_offset(v.back()); });
}

}  // namespace gpsemu
