// `gpsemu base`: a simulated RTK base station (base/base_station.hpp) writing RTCM3 once a second
// to the outputs (--output: udp:HOST:PORT, tcp:[HOST:]PORT a server for many clients, pty:LINK,
// serial:DEVICE[@BAUD], file:PATH, stdout; the one transport interface), paced by the one epoch loop
// and clock (--clock scaled:K, --fast, --start-time, --duration), at --origin. A rover is
// `gpsemu --receiver ublox-f9p --rtcm udp:PORT` on the same clock (docs/rtk.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/app/subcommands.hpp"
#include "emulator/base/base_station.hpp"
#include "emulator/config/config.hpp"
#include "emulator/config/config_values.hpp"
#include "emulator/model/sky/orbits.hpp"
#include "emulator/pipeline/epoch_loop.hpp"
#include "emulator/pipeline/run_settings.hpp"
#include "emulator/pipeline/timeline.hpp"
#include "transport/posix/realtime.hpp"

namespace gpsemu {
namespace {

/// The main options a base reads; any other given on the command line is refused.
constexpr std::array<const char*, 15> kBaseReads = {
    "output", "tee", "origin", "duration", "start-time", "clock", "fast", "latency", "ephemeris", "elevation-mask",
    "seed", "log-level", "realtime-priority", "lock-memory", "timer-slack"};

/// Where the base writes when no --output is given: the rover's `--rtcm udp:2101` on this machine.
constexpr const char* kDefaultOutput = "udp:127.0.0.1:2101";

struct BaseOptions {
  std::string msm = "4";
  std::string systems = "GPS,GLONASS,Galileo,BeiDou,QZSS";
  std::string station_id = "0";
  std::string antenna_height;
};

/// The base's epochs on the 1 Hz grid from `first`, `count` of them (none: until stopped).
class BaseEpochs final : public EpochProducer {
 public:
  BaseEpochs(base::BaseStation& station, UtcNs first, std::optional<std::int64_t> count)
      : station_(station), first_(first), count_(count) {}

  bool next_epoch(UtcNs& t) override {
    if (count_ && next_ >= *count_) return false;
    t = first_ + std::chrono::seconds(next_++);
    return true;
  }
  std::string_view produce(std::size_t, UtcNs t) override {
    epoch_ = station_.epoch(t);
    ++epochs;
    bytes += epoch_.bytes.size();
    for (const std::uint16_t type : epoch_.types) ++by_type[type & 0xFFFu];
    return epoch_.bytes;
  }

  std::uint64_t epochs = 0, bytes = 0;
  std::array<std::uint64_t, 4096> by_type{};

 private:
  base::BaseStation& station_;
  UtcNs first_;
  std::optional<std::int64_t> count_;
  std::int64_t next_ = 0;
  base::BaseEpoch epoch_;
};

/// The base's settings; a bad value throws std::invalid_argument naming its option ("--msm: ...").
base::BaseSettings base_settings(const Config& config, const BaseOptions& o) {
  using namespace config_values;
  const ReceiverSettings& r = config.receiver();
  base::BaseSettings s;
  try {
    s.arp = r.origin;
    s.msm = parse_choice("msm", o.msm, {"4", "7"}) == "7" ? 7 : 4;
    s.systems = base::parse_systems(o.systems);
    const double id = parse_number("station-id", o.station_id, 0, 4095);
    if (id != std::floor(id)) throw std::invalid_argument(fmt::format("station-id: expected a whole number, got '{}'", o.station_id));
    s.station_id = static_cast<std::uint16_t>(id);
    if (!o.antenna_height.empty()) s.antenna_height_m = parse_number("antenna-height", o.antenna_height, 0.0, 6.5535);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("--{}", e.what()));
  }
  s.orbits = r.model.orbits;
  s.elevation_mask_deg = r.model.elevation_mask_deg;
  s.seed = r.seed;
  return s;
}

std::string systems_text(const std::vector<rtk::Gnss>& systems) {
  std::string text;
  for (const rtk::Gnss g : systems) text += fmt::format("{}{}", text.empty() ? "" : ", ", rtk::gnss_name(g));
  return text;
}

int run_base(const Config& config, const BaseOptions& options, const CLI::App& main_app, const std::atomic<bool>& stop) {
  for (const OptionDef& o : option_table()) {
    if (main_app.get_option("--" + o.name)->count() == 0) continue;
    if (std::find(kBaseReads.begin(), kBaseReads.end(), o.name) != kBaseReads.end()) continue;
    throw std::invalid_argument(fmt::format("--{} does not apply to 'gpsemu base' (gpsemu base --help lists what it "
                                            "reads)", o.name));
  }
  TimelineSettings timeline = config.timeline;
  timeline.rate_hz = 1.0;  // a base writes once a second
  if (timeline.clock.kind == ClockKind::lockstep) {
    throw std::invalid_argument("--clock lockstep follows a pose source's time stamps: a base has none (use realtime, "
                                "scaled:K or --fast)");
  }
  const LoopSettings loop = loop_settings(timeline);
  base::BaseSettings settings = base_settings(config, options);
  base::BaseStation station(settings);

  const UtcNs now = system_utc_now();
  const Timeline tl = choose_timeline(1.0, loop.start_time, now);
  ReceiverSettings receiver = config.receiver();
  if (!receiver.outputs_given) receiver.outputs = {transport::parse_output_spec(kDefaultOutput)};
  OutputSettings out = receiver_setup(receiver, timeline).outputs;
  out.rate_hz = 1.0;
  // A serial line must carry an epoch a second: the first epoch's size with a quarter to spare
  // (the sky changes slowly; a wider epoch later is dropped whole and counted).
  const std::size_t widest = base::BaseStation(settings).epoch(tl.first_epoch()).bytes.size() * 5 / 4;
  out.widest_epoch_bytes = [widest] { return widest; };
  Sink sink;
  sink.open(out);
  sink.commit();

  const rtk::BasePosition& arp = station.position();
  spdlog::info("base station {} at {:.7f}, {:.7f}, {:.3f} m MSL (ECEF {:.4f}, {:.4f}, {:.4f} m): {} + MSM{} of {} + 1230 "
               "once a second{}", arp.station_id, settings.arp.lat_deg, settings.arp.lon_deg, settings.arp.alt_m,
               arp.ecef_x_m, arp.ecef_y_m, arp.ecef_z_m,
               settings.antenna_height_m ? fmt::format("1006 (antenna height {} m)", *settings.antenna_height_m) : "1005",
               settings.msm, systems_text(settings.systems),
               loop.epochs ? fmt::format(" for {} s", *loop.epochs) : std::string{});
  sink.log_opened(0, "RTCM3");
  for (const std::string& line : posix::apply_realtime_settings(config.process.realtime)) spdlog::info("{}", line);

  BaseEpochs epochs(station, tl.first_epoch(), loop.epochs);
  std::unique_ptr<SystemClockIo> io = make_loop_io(sink, epochs);
  std::unique_ptr<EpochClock> clock;
  const std::chrono::seconds period{1};
  switch (loop.clock.kind) {
    case ClockKind::fast: clock = std::make_unique<FastClock>(); break;
    case ClockKind::scaled:
      clock = std::make_unique<ScaledClock>(*io, loop.clock.scale, tl.first_epoch(), tl.first_wall() + loop.latency, period);
      break;
    default: clock = std::make_unique<RealtimeClock>(*io, tl.epoch_minus_wall, loop.latency, period); break;
  }
  if (!clock->describe().empty()) spdlog::info("{}", clock->describe());
  EpochLoop epoch_loop(epochs, sink, *clock, LoopOptions{});
  epoch_loop.run(stop);

  std::string types;
  std::uint64_t messages = 0;
  for (std::size_t type = 0; type < epochs.by_type.size(); ++type) {
    if (epochs.by_type[type] == 0) continue;
    messages += epochs.by_type[type];
    types += fmt::format("{}{} x{}", types.empty() ? "" : ", ", type, epochs.by_type[type]);
  }
  spdlog::info("base: {} epochs, {} RTCM3 messages ({}), {} bytes; {} epochs skipped late", epochs.epochs, messages,
               types.empty() ? "none" : types, epochs.bytes, epoch_loop.stats().epochs_late_skipped);
  sink.log_summary(0);
  return epoch_loop.exit_status();
}

}  // namespace

Subcommand add_base_command(CLI::App& app) {
  auto options = std::make_shared<BaseOptions>();
  CLI::App* sub = app.add_subcommand(
      "base",
      "a simulated RTK base station: RTCM3 once a second (1005/1006, MSM4/MSM7 of every system in its sky, 1230) at "
      "--origin to --output (default udp:127.0.0.1:2101, where `gpsemu --receiver ublox-f9p --rtcm udp:2101` "
      "listens); --duration, --clock scaled:K, --fast as for the emulator (docs/rtk.md)");
  sub->add_option("--msm", options->msm, "observation messages: 4 (MSM4: 1074, 1084, 1094, 1114, 1124) or 7 (MSM7: "
                  "1077 ...) (default 4)")->option_text("N");
  sub->add_option("--systems", options->systems, "systems observed, comma-separated, from GPS, GLONASS, Galileo, BeiDou, "
                  "QZSS (default all five)")->option_text("LIST");
  sub->add_option("--station-id", options->station_id, "reference station id (DF003), 0..4095 (default 0)")
      ->option_text("N");
  sub->add_option("--antenna-height", options->antenna_height, "antenna height above the marker, 0..6.5535 metres: "
                  "1006 with it instead of 1005 (default: 1005)")->option_text("M");
  sub->footer("Of the options of gpsemu it reads only: --origin LAT,LON,ALT (the antenna reference point; default the "
              "emulator's 43.0725,-89.4125,260), --output SPEC (repeatable), --tee FILE, --duration S, --clock "
              "realtime|scaled:K, --fast, --start-time, --latency S, --ephemeris FILE, --elevation-mask DEG, --seed N, "
              "--log-level, --realtime-priority, --lock-memory, --timer-slack; any other is refused (exit 2).\n"
              "Example: gpsemu base --clock scaled:10 & gpsemu --receiver ublox-f9p --rtcm udp:2101 --clock scaled:10");
  return {sub, [options, &app](const Config& config, const std::atomic<bool>& stop) {
            return run_base(config, *options, app, stop);
          }};
}

}  // namespace gpsemu
