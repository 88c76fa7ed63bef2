#include "emulator/config/config_options.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/config/config_values.hpp"
#include "emulator/config/profiles.hpp"
#include "emulator/config/spec/control_spec.hpp"
#include "emulator/config/spec/pps_spec.hpp"
#include "emulator/model/receiver_models.hpp"
#include "emulator/sources/pose_message.hpp"
#include "emulator/ui/ui_spec.hpp"

namespace gpsemu {
namespace {

using V = const std::vector<std::string>&;
using namespace config_values;

nmea::FixQuality parse_fix_quality(const std::string& text, const char* key = "fix-quality") {
  const std::string q = parse_choice(key, text, {"gps", "dgps", "rtk-float", "rtk-fixed"});
  if (q == "dgps") return nmea::FixQuality::dgps;
  if (q == "rtk-float") return nmea::FixQuality::rtk_float;
  if (q == "rtk-fixed") return nmea::FixQuality::rtk_fixed;
  return nmea::FixQuality::gps;
}

// "START+DURATION" in seconds, e.g. "30+5".
Outage parse_outage(const std::string& text) {
  const auto plus = text.find('+', 1);  // a leading '+' is the sign of START
  if (plus == std::string::npos) {
    throw std::invalid_argument(fmt::format("outage: expected START+DURATION in seconds, e.g. 30+5, got '{}'", text));
  }
  const double start_s = parse_number("outage START", text.substr(0, plus), 0.0, 1e9);
  const double duration_s = parse_number("outage DURATION", text.substr(plus + 1), 0.0, 1e9);
  if (!(duration_s > 0.0)) throw std::invalid_argument(fmt::format("outage: DURATION must be > 0 seconds, got '{}'", text));
  return {start_s, duration_s};
}

// Comma-separated sentence names (case-insensitive), from one or several values.
nmea::SentenceSet parse_sentence_set(const std::vector<std::string>& values) {
  nmea::SentenceSet set;
  for (const std::string& value : values) {
    std::size_t start = 0;
    while (start <= value.size()) {
      const std::size_t comma = std::min(value.find(',', start), value.size());
      std::string token = value.substr(start, comma - start);
      std::erase_if(token, [](unsigned char ch) { return std::isspace(ch) != 0; });
      std::transform(token.begin(), token.end(), token.begin(), [](unsigned char ch) { return std::toupper(ch); });
      const auto type = nmea::sentence_type_from_name(token);
      if (!type) {
        throw std::invalid_argument(fmt::format("sentences: unknown sentence '{}' in '{}' (accepted: RMC, VTG, GGA, "
                                                "GSA, GSV, GLL, GST, ZDA, HDT, THS)", token, value));
      }
      set.insert(*type);
      start = comma + 1;
    }
  }
  if (set.empty()) throw std::invalid_argument("sentences: at least one sentence type is needed");
  return set;
}

}  // namespace

std::vector<OptionDef> make_option_table() {
  std::vector<OptionDef> t;
  // The scope of the options that follow (OptionScope): set once per group below.
  OptionScope scope = OptionScope::receiver;
  auto add = [&t, &scope](std::string name, std::string value_name, std::string help,
                          std::function<void(ConfigDraft&, V)> apply, bool repeatable = false) {
    t.push_back({std::move(name), std::move(value_name), std::move(help), scope, repeatable, std::move(apply)});
  };
  // Pose source
  scope = OptionScope::receiver;
  add("source", "SPEC", "pose source: sim:stationary | sim:line | sim:circle | sim:waypoints:FILE | replay:FILE.csv (a recorded truth trajectory) | udp:[HOST:]PORT | tcp:[HOST:]PORT (JSON poses from a simulator; HOST default 127.0.0.1) | mavlink:udp:[HOST:]PORT | mavlink:tcp:HOST:PORT (SIM_STATE, HIL_STATE_QUATERNION or SIMSTATE from ArduPilot/PX4 SITL: listen for datagrams, or connect), e.g. sim:circle or "
      "udp:5005 (default sim:stationary)",
      [](ConfigDraft& d, V v) { d.receiver.source = v.back(); });
  add("origin", "LAT,LON,ALT", "local frame origin: degrees, degrees, metres above MSL (-10000..1000000), e.g. "
      "52.5163,13.3777,34 (default 43.0725,-89.4125,260)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("origin", v.back(), 3, 3);
        if (x[0] < -90.0 || x[0] > 90.0) throw std::invalid_argument(fmt::format("origin latitude {} is outside [-90, 90]", x[0]));
        if (x[1] < -180.0 || x[1] > 180.0) throw std::invalid_argument(fmt::format("origin longitude {} is outside [-180, 180]", x[1]));
        if (x[2] < sources::kMinAltM || x[2] > sources::kMaxAltM) {
          throw std::invalid_argument(fmt::format("origin altitude {} m is outside [{}, {}] m (the range a pose may have)",
                                                  x[2], sources::kMinAltM, sources::kMaxAltM));
        }
        d.receiver.settings.origin = {x[0], x[1], x[2]};
      });
  add("sim-speed", "MPS", "simulated speed for line, circle and waypoints, m/s (default 2)",
      [](ConfigDraft& d, V v) { d.receiver.settings.sim.speed_mps = parse_number("sim-speed", v.back(), 0.001, 1000.0); });
  add("sim-heading", "DEG", "sim:line heading, degrees true (default 90 = east)",
      [](ConfigDraft& d, V v) { d.receiver.settings.sim.heading_deg = parse_number("sim-heading", v.back(), 0.0, 360.0); });
  add("sim-drive-time", "S", "sim:line seconds of driving before it stops (default 20)",
      [](ConfigDraft& d, V v) { d.receiver.settings.sim.drive_time_s = parse_number("sim-drive-time", v.back(), 0.0, 1e7); });
  add("sim-radius", "M", "sim:circle radius, metres (default 20)",
      [](ConfigDraft& d, V v) { d.receiver.settings.sim.radius_m = parse_number("sim-radius", v.back(), 0.1, 1e6); });
  add("sim-loop", "", "sim:waypoints: start over after the last waypoint (default off)",
      [](ConfigDraft& d, V v) { d.receiver.settings.sim.loop = parse_bool("sim-loop", v.back()); });
  add("pose-timeout", "S", "udp:/tcp: a pose older than this means no fix until poses resume, seconds, "
      "0.05..60 (default 1)",
      [](ConfigDraft& d, V v) { d.receiver.settings.pose_timeout_s = parse_number("pose-timeout", v.back(), 0.05, 60.0); });
  add("pose-horizon", "S", "udp:/tcp: extrapolate past the newest pose with its velocity for at most this long, "
      "then hold it, seconds, 0..pose-timeout (default 0.2)",
      [](ConfigDraft& d, V v) { d.receiver.settings.pose_horizon_s = parse_number("pose-horizon", v.back(), 0.0, 60.0); });
  // Clock
  scope = OptionScope::timeline;
  add("rate", "HZ", "epochs per second: 1..50 whole, or 0.5/0.25/0.2/0.1 (default 1)",
      [](ConfigDraft& d, V v) {
        d.timeline.rate_hz = parse_number("rate", v.back(), 0.1, 50.0);
        (void)EpochGrid(d.timeline.rate_hz);  // validates the grid
      });
  add("latency", "S", "delay from epoch time to first byte, seconds, 0..0.5 (default 0.05)",
      [](ConfigDraft& d, V v) { d.timeline.latency_s = parse_number("latency", v.back(), 0.0, 0.5); });
  add("start-time", "ISO8601", "UTC time of the first epoch, YYYY-MM-DDThh:mm:ss[.fff]Z (the Z is required; "
      "no offsets), e.g. 2024-05-01T12:00:00Z (default: now)",
      [](ConfigDraft& d, V v) { d.timeline.start_time = parse_iso8601_utc(v.back(), UtcSuffix::required); });
  add("duration", "S", "stop after this many seconds of epochs (default: run until stopped)",
      [](ConfigDraft& d, V v) { d.timeline.duration_s = parse_number("duration", v.back(), 0.0, 1e9); });
  add("fast", "", "no pacing: generate epochs as fast as possible (batch generation, tests)",
      [](ConfigDraft& d, V v) { d.fast = parse_bool("fast", v.back()); });
  add("scenario", "FILE", "faults on a timeline: a TOML file of [[fault]] tables (kind, at, duration, parameters "
      "with units; docs/faults.md), or a --tee file to replay its live faults; repeatable: the files' faults add up "
      "in the order given; [[fault]] tables may also be in --config (default none)",
      [](ConfigDraft& d, V v) {
        for (const std::string& file : v) {
          for (faults::Fault& f : load_scenario(file)) d.timeline.faults.push_back(std::move(f));
        }
      }, true);
  add("clock", "CLOCK", "epoch clock: realtime | scaled:K (paced at K x real time, K 0.01..1000; NMEA times still "
      "one epoch period apart) | fast (as --fast) | lockstep (an epoch leaves when the 't' of udp:/tcp: poses "
      "reaches it; t = 0 is --start-time or the first epoch), e.g. scaled:10 (default realtime)",
      [](ConfigDraft& d, V v) { d.timeline.clock = parse_clock_spec(v.back()); });
  // Replay (gpsemu replay LOG)
  scope = OptionScope::replay;
  add("speed", "K", "replay: speed factor, 0.1..100; 10 sends 1 s of log every 100 ms (default 1)",
      [](ConfigDraft& d, V v) { d.replay.speed = parse_number("speed", v.back(), 0.1, 100.0); });
  add("loop", "", "replay: start over after the last epoch (default off)",
      [](ConfigDraft& d, V v) { d.replay.loop = parse_bool("loop", v.back()); });
  add("from", "WHEN", "replay: first epoch sent: time of day hh:mm:ss[.ss] (UTC, as in the log) or epoch index "
      "from 0, e.g. 12:30:00 or 100 (default: the first)",
      [](ConfigDraft& d, V v) { d.replay.from = replay::parse_log_position("from", v.back()); });
  add("to", "WHEN", "replay: last epoch sent (included): hh:mm:ss[.ss] or epoch index (default: the last)",
      [](ConfigDraft& d, V v) { d.replay.to = replay::parse_log_position("to", v.back()); });
  add("retime", "", "replay: rewrite time and date fields to the present (or --start-time) and recompute "
      "checksums, so clients see a live receiver (default off: bytes sent unchanged)",
      [](ConfigDraft& d, V v) { d.replay.retime = parse_bool("retime", v.back()); });
  // A receiver profile: its keys are applied first (config.cpp), so every other option overrides them.
  scope = OptionScope::process;
  add("profile", "NAME", "a real receiver's calibrated noise, state and model by name, e.g. ublox-zed-f9p "
      "(`gpsemu profiles` lists them); the config file's keys and the flags override its own (default none)",
      [](ConfigDraft&, V v) { (void)profiles::get(v.back()); });
  // Noise
  scope = OptionScope::receiver;
  add("noise", "MODEL", "noise model: cgrw | chrono | gaussian | gauss-markov | composite (smooth wander + white jitter + "
      "jumps) | none (default cgrw)",
      [](ConfigDraft& d, V v) { d.receiver.settings.noise.model = noise::parse_model(v.back()); });
  add("width", "M", "cgrw one knob: horizontal wander max-min, metres (0.1 high accuracy, 1 default, 10 poor)",
      [](ConfigDraft& d, V v) { d.receiver.width_m = parse_number("width", v.back(), 0.001, 1000.0); });
  add("seed", "N", "random seed; same seed, inputs and start time give identical output (default 1)",
      [](ConfigDraft& d, V v) { d.receiver.settings.seed = parse_uint("seed", v.back()); });
  for (const char* axis : {"east", "north", "up"}) {
    add(fmt::format("cgrw-{}", axis), "W,W1,W2,S2",
        fmt::format("cgrw {} axis: width, first- and second-difference widths, second-difference std, metres "
                    "at cgrw-rate; 0,0,0,0: no noise on the axis (default: from --width)", axis),
        [axis](ConfigDraft& d, V v) {
          const auto a = parse_cgrw_axis(fmt::format("cgrw-{}", axis), v.back());
          std::string name = axis;
          (name == "east" ? d.receiver.cgrw_east : name == "north" ? d.receiver.cgrw_north : d.receiver.cgrw_up) = a;
        });
  }
  add("cgrw-rate", "HZ", "rate the cgrw-east/north/up parameters were measured at, Hz (default 1; needs all three axes)",
      [](ConfigDraft& d, V v) { d.receiver.cgrw_rate_hz = parse_number("cgrw-rate", v.back(), 0.01, 1000.0); });
  add("cgrw-window", "S", "time span the cgrw widths were measured over, seconds (default 300)",
      [](ConfigDraft& d, V v) { d.receiver.settings.noise.cgrw.window_s = parse_number("cgrw-window", v.back(), 1.0, 1e6); });
  add("gaussian-sigma", "S[,SN,SU]", "gaussian standard deviation east,north,up, metres (default 1,1,1)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("gaussian-sigma", v.back(), 1, 3);
        for (std::size_t i = 0; i < 3; ++i) {
          const double s = x[std::min(i, x.size() - 1)];
          if (s < 0.0) throw std::invalid_argument("gaussian-sigma must be >= 0 metres");
          d.receiver.settings.noise.gaussian[i].sigma_m = s;
        }
      });
  add("gaussian-mean", "M[,MN,MU]", "gaussian mean east,north,up, metres (default 0,0,0)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("gaussian-mean", v.back(), 1, 3);
        for (std::size_t i = 0; i < 3; ++i) d.receiver.settings.noise.gaussian[i].mean_m = x[std::min(i, x.size() - 1)];
      });
  add("chrono", "MEAN,SIGMA,RATE[,VMAX,AMAX]",
      "chrono model: Project Chrono 9 ChNoiseRandomWalks arguments: mean (ignored, as in Chrono), "
      "sigma m/s^2, update rate Hz, max velocity m/s, max acceleration m/s^2 "
      "(default 0,0.0163,1,0.03,0.005)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("chrono", v.back(), 3, 5);
        noise::ChronoParams p = d.receiver.settings.noise.chrono;
        p.mean = x[0];
        p.sigma = x[1];
        p.update_rate_hz = x[2];
        if (x.size() > 3) p.v_max_mps = x[3];
        if (x.size() > 4) p.a_max_mps2 = x[4];
        if (!(p.sigma >= 0.0)) throw std::invalid_argument(fmt::format("chrono: SIGMA must be >= 0 m/s^2, got '{}'", v.back()));
        if (!(p.update_rate_hz > 0.0) || p.update_rate_hz > 10000.0)
          throw std::invalid_argument(fmt::format("chrono: RATE must be > 0 and <= 10000 Hz, got '{}'", v.back()));
        if (!(p.v_max_mps >= 0.0) || !(p.a_max_mps2 >= 0.0))
          throw std::invalid_argument(fmt::format("chrono: VMAX and AMAX must be >= 0, got '{}'", v.back()));
        d.receiver.settings.noise.chrono = p;
      });
  add("gm-sigma", "S[,SN,SU]", "gauss-markov stationary standard deviation east,north,up, metres (default 1,1,1)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("gm-sigma", v.back(), 1, 3);
        for (std::size_t i = 0; i < 3; ++i) {
          const double s = x[std::min(i, x.size() - 1)];
          if (s < 0.0) throw std::invalid_argument(fmt::format("gm-sigma must be >= 0 metres, got '{}'", v.back()));
          d.receiver.settings.noise.gauss_markov[i].sigma_m = s;
        }
      });
  add("gm-tau", "T[,TN,TU]", "gauss-markov correlation time east,north,up, seconds > 0 (default 60,60,60)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("gm-tau", v.back(), 1, 3);
        for (std::size_t i = 0; i < 3; ++i) {
          const double t = x[std::min(i, x.size() - 1)];
          if (!(t > 0.0)) throw std::invalid_argument(fmt::format("gm-tau must be > 0 seconds, got '{}'", v.back()));
          d.receiver.settings.noise.gauss_markov[i].tau_s = t;
        }
      });
  add("gm-order", "N", "gauss-markov order: 1 (first order) or 2 (second order, smooth like a receiver's "
      "filtered position; autocorrelation (1+t/tau)exp(-t/tau)) (default 1)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.noise.gauss_markov_order = static_cast<int>(parse_number("gm-order", v.back(), 1, 2));
        if (parse_number("gm-order", v.back(), 1, 2) != d.receiver.settings.noise.gauss_markov_order)
          throw std::invalid_argument(fmt::format("gm-order must be 1 or 2, got '{}'", v.back()));
      });
  add_composite_options(t);
  // Receiver and sentences
  scope = OptionScope::receiver;
  add("satellites", "N", "at most N satellites used in a fix, 4..64 (default: every one above the elevation mask "
      "and the C/N0 threshold, within the model's channels)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.satellites_used = static_cast<int>(parse_number("satellites", v.back(), 4, 64)); });
  add("hdop", "X", "HDOP reported with a fix, 0.5..50; VDOP and PDOP scale alike (default: from the geometry of "
      "the satellites used)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.hdop = parse_number("hdop", v.back(), 0.5, 50.0); });
  add("ephemeris", "FILE", "RINEX 2/3 navigation file: the true sky of its date (default: the embedded sky, a real "
      "merged RINEX file of 2026-03-09 at the same sidereal time; docs/sky.md)",
      [](ConfigDraft& d, V v) { d.receiver.settings.ephemeris = v.back(); });
  add("elevation-mask", "DEG", "satellites below this elevation are tracked but not used, 0..60 degrees "
      "(default: the model's, 5)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.elevation_mask_deg = parse_number("elevation-mask", v.back(), 0.0, 60.0); });
  add("sky-mask", "SPEC", "obstructions: urban-canyon | open | FROM-TO:ELEV[,...] azimuth sectors (degrees true) "
      "and the elevation below which nothing is received there (default open)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.sky_mask = parse_sky_mask(v.back()); });
  add("hold-radius", "M", "static hold: while slower than --hold-speed the receiver repeats its last position until its "
      "own position wanders farther than this from it, 0..100 metres (default 0 = off; calibrate fits it from the "
      "log's share of repeated positions)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.hold.radius_m = parse_number("hold-radius", v.back(), 0.0, 100.0); });
  add("hold-speed", "MPS", "static hold: speed over ground below which the position is held, 0..10 m/s (default 0.3)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.hold.max_speed_mps = parse_number("hold-speed", v.back(), 0.0, 10.0); });
  add("velocity-noise", "MPS", "white part of the reported velocity's error, 1 sigma per horizontal axis, 0..10 m/s "
      "(Doppler jitter, apart from the position's wander; default 0.03, 0 with --noise none; calibrate fits it from "
      "the speed a log reports at rest)",
      [](ConfigDraft& d, V v) { d.receiver.velocity_white_mps = parse_number("velocity-noise", v.back(), 0.0, 10.0); });
  add("velocity-wander", "MPS", "slow correlated part of the velocity's error (first-order Gauss-Markov), stationary 1 "
      "sigma per horizontal axis, 0..10 m/s (default 0.02, 0 with --noise none)",
      [](ConfigDraft& d, V v) { d.receiver.velocity_wander_mps = parse_number("velocity-wander", v.back(), 0.0, 10.0); });
  add("velocity-wander-tau", "S", "correlation time of --velocity-wander, 0.1..86400 seconds (default 10)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.model.velocity.wander_tau_s = parse_number("velocity-wander-tau", v.back(), 0.1, 86400.0);
      });
  add("velocity-static-clamp", "MPS", "report a speed below this as 0 (no course), as Quectel and SkyTraq chipsets do "
      "standing still, 0..1 m/s (default 0 = never)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.model.velocity.static_clamp_mps = parse_number("velocity-static-clamp", v.back(), 0.0, 1.0);
      });
  add("course-at-rest", "MODE", "the course reported while slower than --course-min-speed: empty (u-blox) | held (the "
      "last one: SiRF, SkyTraq, Quectel) | measured (from the noisy velocity at any speed) (default empty)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.course_at_rest = parse_course_at_rest(v.back()); });
  add("course-min-speed", "MPS", "speed over ground below which the course is --course-at-rest's, 0..10 m/s (default 0.4)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.model.course_min_speed_mps = parse_number("course-min-speed", v.back(), 0.0, 10.0);
      });
  add("uere", "M", "user equivalent range error of an autonomous fix, metres, 0.05..50: GST's range RMS and, with "
      "--noise none, the reported accuracy = DOP x UERE x the fix quality's scale (default: the model's; "
      "calibrate writes it)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.uere_m = parse_number("uere", v.back(), 0.05, 50.0); });
  add("noise-scales-with-dop", "", "the emulated error grows with HDOP/1.0 horizontally and VDOP/1.5 vertically "
      "(default off)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.noise_scales_with_dop = parse_bool("noise-scales-with-dop", v.back()); });
  add("fix-quality", "Q", "fix quality: gps | dgps | rtk-float | rtk-fixed; scales the noise by 1, 0.4, 0.1, "
      "0.01 relative to --noise-quality (default gps)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.quality = parse_fix_quality(v.back()); });
  add("noise-quality", "Q", "the fix quality the noise parameters were measured at: gps | dgps | rtk-float | "
      "rtk-fixed; a calibrated RTK rover's noise is its own at rtk-fixed, and grows by the scales' ratio when "
      "its fix falls back (default gps; calibrate writes it)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.noise_quality = parse_fix_quality(v.back(), "noise-quality"); });
  add("accuracy-ratio", "R", "reported accuracy (GST, hAcc, vAcc, eph) / the error actually applied, 0.01..10: 1 "
      "is an honest receiver, real ones are often optimistic (default 1; calibrate measures it from a log "
      "with GST)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.accuracy_ratio = parse_number("accuracy-ratio", v.back(), 0.01, 10.0); });
  add("cold-start", "S[,S2D]", "cold start: no fix for S seconds (satellites acquired one by one), then a "
      "2-D fix for S2D seconds (default 2 when S > 0), then 3-D; seconds after the first epoch (default 0,0)",
      [](ConfigDraft& d, V v) {
        const auto x = parse_list("cold-start", v.back(), 1, 2);
        if (x[0] < 0.0 || (x.size() > 1 && x[1] < 0.0) || x[0] > 1e6 || (x.size() > 1 && x[1] > 1e6)) {
          throw std::invalid_argument(fmt::format("cold-start: seconds must be 0..1e6, got '{}'", v.back()));
        }
        d.receiver.settings.model.cold_start_s = x[0];
        d.receiver.settings.model.cold_start_2d_s = x.size() > 1 ? x[1] : (x[0] > 0.0 ? 2.0 : 0.0);
      });
  add("outage", "START+DURATION", "scheduled outage (tunnel): no satellites and no fix from START for "
      "DURATION seconds, START in seconds after the first epoch; repeatable, e.g. 30+5 (default none)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.model.outages.clear();
        for (const auto& text : v) d.receiver.settings.model.outages.push_back(parse_outage(text));
      }, true);
  add("sentences", "LIST", "NMEA sentences of each epoch, comma-separated, from RMC VTG GGA GSA GSV GLL GST "
      "ZDA HDT THS (true heading: needs a pose with yaw_deg; not u-blox messages); written in that order whatever the order given, e.g. GGA,RMC (default RMC,VTG,GGA,GSA,GSV,GLL)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.format.sentences = parse_sentence_set(v);
        d.receiver.settings.sentences_given = true;
      });
  add("protocol", "P", "what the receiver writes at start: nmea | ubx (u-blox binary, answering its configuration "
      "handshake; NMEA only with --sentences) | nmea+ubx (default nmea; with a --receiver ublox-* model: its factory "
      "state, NMEA written and UBX answered on the port)",
      [](ConfigDraft& d, V v) {
        const std::string p = parse_choice("protocol", v.back(), {"nmea", "ubx", "nmea+ubx"});
        d.receiver.settings.protocol = p == "ubx" ? Protocol::ubx : p == "nmea" ? Protocol::nmea : Protocol::nmea_ubx;
        d.receiver.settings.protocol_given = true;
      });
  add("receiver", "MODEL", "the u-blox receiver emulated: ublox-m8n | ublox-m9n | ublox-f9p | ublox-m10 (alone: the model's "
      "factory state, its NMEA and baud, UBX answered) | generic (NMEA only unless --protocol says; answers as an M8) "
      "(default generic)",
      [](ConfigDraft& d, V v) {
        // The names are the receiver table's (model/receiver_models.cpp): a new row is a new --receiver.
        const std::optional<ReceiverModel> model = receiver_model_from_name(v.back());
        if (!model) throw std::invalid_argument(fmt::format("receiver must be one of {}, got '{}'", receiver_model_names(), v.back()));
        d.receiver.settings.receiver_model = *model;
      });
  add("receiver-state", "FILE", "a u-blox's stored configuration (BBR and flash layers: CFG-VALSET to them, "
      "CFG-CFG save) read at start when FILE exists and written whenever it changes, so a saved configuration "
      "survives a restart; with several receivers one file each, e.g. gps{i}.state (default none: every run starts "
      "from the defaults)",
      [](ConfigDraft& d, V v) { d.receiver.settings.receiver_state = v.back(); });
  add("geoid-separation", "M", "geoid separation in GGA, metres (default: the EGM96 geoid at the origin)",
      [](ConfigDraft& d, V v) { d.receiver.settings.model.geoid_sep_m = parse_number("geoid-separation", v.back(), -120.0, 120.0); });
  add("talker", "ID", "NMEA talker ID of GGA, RMC and the others: GP (GPS) | GN (several systems) | GL (GLONASS) | "
      "GA (Galileo) | BD (BeiDou) (default: GN when the model tracks several systems, as u-blox does; GSV always "
      "has each system's own)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.format.talker = parse_choice("talker", v.back(), {"GP", "GN", "GL", "GA", "BD"});
        d.receiver.settings.talker_given = true;
      });
  add("nmea-version", "V", "NMEA version: 2.3 or 4.1 (default 4.1)",
      [](ConfigDraft& d, V v) {
        d.receiver.settings.format.version = parse_choice("nmea-version", v.back(), {"2.3", "4.1"}) == "2.3" ? nmea::NmeaVersion::v2_3
                                                                                             : nmea::NmeaVersion::v4_1;
      });
  add("resolution", "N", "decimals of minutes in latitude/longitude, 1..8 (default 5, about 1.85 cm)",
      [](ConfigDraft& d, V v) { d.receiver.settings.format.minute_decimals = static_cast<int>(parse_number("resolution", v.back(), 1, 8)); });
  add("time-decimals", "N", "decimals of seconds in NMEA times, 0..3 (default 2)",
      [](ConfigDraft& d, V v) { d.receiver.settings.format.time_decimals = static_cast<int>(parse_number("time-decimals", v.back(), 0, 3)); });
  add("alt-decimals", "N", "decimals of the GGA altitude, 0..4 (default 1, 0.1 m steps; calibrate learns it from the log)",
      [](ConfigDraft& d, V v) { d.receiver.settings.format.alt_decimals = static_cast<int>(parse_number("alt-decimals", v.back(), 0, 4)); });
  // Outputs and logging
  scope = OptionScope::receiver;
  add("output", "SPEC", "where NMEA goes, repeatable: pty[:LINK] | file:PATH[?mode=append|new] (truncated unless append; new: must not exist) | stdout | serial:DEVICE[@BAUD] | "
      "serial:usb:VID:PID[:SERIAL][@BAUD] (8N1; BAUD 4800..921600, default 9600) | tcp:[HOST:]PORT (server; HOST "
      "default 127.0.0.1) | udp:HOST:PORT, e.g. pty:/tmp/gps or serial:/dev/ttyUSB0@115200 (default pty:/tmp/gpsemu)",
      [](ConfigDraft& d, V v) {
        d.receiver.outputs = v;
        d.receiver.settings.outputs_given = true;
      }, true);
  add("tee", "FILE", "also write everything sent to FILE, each epoch after a '# sent <UTC send time>' line "
      "(gpsemu replay reads it back; truncated) (default none)",
      [](ConfigDraft& d, V v) { d.receiver.tee = v.back(); });
  // PPS
  scope = OptionScope::pps;
  add("pps", "SPEC", "PPS pulse, leading edge at each whole UTC second: gpio:CHIP:LINE (libgpiod; CHIP "
      "/dev/gpiochipN, name or label; LINE offset or name) | modem:RTS | modem:DTR (on the serial output), "
      "e.g. gpio:gpiochip0:17 (default: none)",
      [](ConfigDraft& d, V v) {
        d.timeline.pps = transport::parse_pps_spec(v.back());
      });
  add("pps-width", "S", "PPS pulse width, seconds, 0.001..0.9 (default 0.1)",
      [](ConfigDraft& d, V v) { d.timeline.pps_width_s = parse_number("pps-width", v.back(), 0.001, 0.9); });
  add("pps-polarity", "LEVEL", "PPS line level during the pulse: high (GPIO 1, modem line asserted) | low "
      "(default high)",
      [](ConfigDraft& d, V v) { d.timeline.pps_active_low = parse_choice("pps-polarity", v.back(), {"high", "low"}) == "low"; });
  // Scheduling (real-time pacing)
  scope = OptionScope::process;
  add("control", "SPEC", "live faults: unix:PATH (a Unix socket) or tcp:[HOST:]PORT (HOST default 127.0.0.1; port 0: "
      "any, logged) taking JSON lines, e.g. {\"fault\":\"jam\",\"db\":25}, {\"clear\":\"jam\"}, {\"status\":true}; "
      "`gpsemu ctl PATH ...` is its client (docs/faults.md) (default none)",
      [](ConfigDraft& d, V v) { d.process.control_path = parse_control_spec(v.back()); });
  add("control-idle-timeout", "S", "--control: close a client that sent no request for this long, seconds, 0..86400 "
      "(0: never; at most 8 clients at once) (default 30)",
      [](ConfigDraft& d, V v) { d.process.control_idle_timeout_s = parse_number("control-idle-timeout", v.back(), 0.0, 86400.0); });
  add("ui", "[HOST:]PORT", "the bench view: a page served at http://HOST:PORT/ (HOST default 127.0.0.1; port 0: any, "
      "logged) with the sky, C/N0, the error against the truth, the faults as buttons and the link, live at the epoch "
      "rate; another HOST than loopback needs a token for every change (docs/ui.md) (default none)",
      [](ConfigDraft& d, V v) {
        (void)ui::parse_ui_spec(v.back());
        d.process.ui = v.back();
      });
  add("ui-token", "TOKEN", "--ui: the token a fault request must carry (header X-Gpsemu-Token), at least 8 characters "
      "(default: a random one, printed at start, when --ui binds another address than loopback; none on loopback)",
      [](ConfigDraft& d, V v) {
        if (v.back().size() < 8) throw std::invalid_argument("ui-token: expected at least 8 characters");
        d.process.ui_token = v.back();
      });
  add("status-every", "S", "a status line in the log every S seconds, 0..86400: fix, satellites, HDOP, error against "
      "the truth, bytes/s, late epochs, active faults (0: never; tools/run: 10) (default 0)",
      [](ConfigDraft& d, V v) { d.process.status_every_s = parse_number("status-every", v.back(), 0.0, 86400.0); });
  add("realtime-priority", "N", "run with SCHED_FIFO priority N, 1..99, where permitted (else a warning and normal "
      "scheduling) (default: normal scheduling)",
      [](ConfigDraft& d, V v) { d.process.realtime.fifo_priority = static_cast<int>(parse_number("realtime-priority", v.back(), 1, 99)); });
  add("lock-memory", "", "lock the process's memory (mlockall) where permitted: no page faults in the loop (default off)",
      [](ConfigDraft& d, V v) { d.process.realtime.lock_memory = parse_bool("lock-memory", v.back()); });
  add("timer-slack", "NS", "timer slack, nanoseconds, 1..50000000 (1: wake at the deadline; kernel default 50000)",
      [](ConfigDraft& d, V v) { d.process.realtime.timer_slack_ns = static_cast<long>(parse_number("timer-slack", v.back(), 1, 5e7)); });
  add("log-level", "LEVEL", "trace | debug | info | warn | error | off (default info)",
      [](ConfigDraft& d, V v) {
        d.process.log_level = parse_choice("log-level", v.back(), {"trace", "debug", "info", "warn", "error", "off"});
      });
  // Many receivers in one process
  scope = OptionScope::fleet;
  add("receivers", "N", "number of independent receivers in this process, 1..1024, each with its own outputs, "
      "source and seed: {i} in output, source, tee and rtcm is the receiver's index (0..N-1), {B+i} is B plus it, "
      "and receiver i's seed is seed + i; or one [[receiver]] table each in the config file (default 1)",
      [](ConfigDraft& d, V v) {
        const double n = parse_number("receivers", v.back(), 1, kMaxReceivers);
        if (n != std::floor(n)) throw std::invalid_argument(fmt::format("receivers must be a whole number, got '{}'", v.back()));
        d.receivers = static_cast<int>(n);
        d.receivers_given = true;
      });
  add_rtk_options(t);
  return t;
}

}  // namespace gpsemu
