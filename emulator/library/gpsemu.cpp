// The library facade (emulator/library/gpsemu.hpp): one receiver channel (pipeline/channel.hpp) on
// the timeline the emulator would choose (pipeline/timeline.hpp), stepped by the caller: no
// outputs, PPS or pacing.
#include "emulator/library/gpsemu.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "emulator/config/config.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/time.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/faults/control.hpp"
#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/control_socket.hpp"
#include "emulator/pipeline/run_settings.hpp"
#include "emulator/pipeline/timeline.hpp"

namespace gpsemu::api {
namespace {

Config make_config(const Options& options, const std::optional<std::string>& config_file) {
  try {
    return build_config(config_file, options);
  } catch (const std::exception& e) {
    throw Error(e.what());
  }
}

gpsemu::Enu to_internal(const Enu& v) { return {v[0], v[1], v[2]}; }
Enu to_api(const gpsemu::Enu& v) { return {v.east_m, v.north_m, v.up_m}; }

}  // namespace

// ---------------------------------------------------------------------------------------------
struct NoiseGenerator::Impl {
  std::unique_ptr<noise::NoiseModel> model;
  std::int64_t next_ns = 0;  ///< time of the next generate() sample
  std::int64_t last_ns = std::numeric_limits<std::int64_t>::min();
};

NoiseGenerator::NoiseGenerator(const Options& options, const std::optional<std::string>& config_file)
    : impl_(std::make_unique<Impl>()) {
  const Config config = make_config(options, config_file);
  try {
    impl_->model = noise::make_noise_model(config.receiver().noise, config.receiver().seed);
  } catch (const std::exception& e) {
    throw Error(e.what());
  }
}
NoiseGenerator::~NoiseGenerator() = default;
NoiseGenerator::NoiseGenerator(NoiseGenerator&&) noexcept = default;
NoiseGenerator& NoiseGenerator::operator=(NoiseGenerator&&) noexcept = default;

Enu NoiseGenerator::at(std::int64_t since_start_ns) {
  if (since_start_ns < impl_->last_ns) throw Error("NoiseGenerator: query times must not decrease");
  impl_->last_ns = since_start_ns;
  return to_api(impl_->model->offset_at(std::chrono::nanoseconds{since_start_ns}));
}

void NoiseGenerator::generate(std::size_t n, double rate_hz, double* out_enu_m) {
  if (!(rate_hz > 0.0) || rate_hz > 1e6) throw Error("generate: rate must be > 0 and <= 1e6 Hz");
  const double period_ns = 1e9 / rate_hz;
  const std::int64_t start = impl_->next_ns;
  for (std::size_t k = 0; k < n; ++k) {
    const Enu e = at(start + std::llround(static_cast<double>(k) * period_ns));
    out_enu_m[3 * k] = e[0];
    out_enu_m[3 * k + 1] = e[1];
    out_enu_m[3 * k + 2] = e[2];
  }
  impl_->next_ns = start + std::llround(static_cast<double>(n) * period_ns);
}

// ---------------------------------------------------------------------------------------------
struct Receiver::Impl {
  Impl(ReceiverSetup r, const LoopSettings& loop)
      : setup(std::move(r)),
        rate_hz(loop.rate_hz),
        // The first epoch as the emulator chooses it: the first grid epoch at or after
        // --start-time, else the next one after now.
        timeline(choose_timeline(loop.rate_hz, loop.start_time, system_utc_now())),
        channel(setup.channel, timeline.first_epoch()) {}
  ReceiverSetup setup;
  double rate_hz;
  Timeline timeline;
  Channel channel;  ///< never moves (held by unique_ptr): its receiver refers to its frame
  std::int64_t k = 0;  ///< epochs reported so far

  [[nodiscard]] UtcNs next_time() const { return timeline.grid.time_of(timeline.first_index + k); }

  Epoch report(UtcNs t, const nmea::Fix& fix) {
    ++k;
    const LocalFrame& frame = channel.frame();
    Epoch e;
    e.time_ns = t.time_since_epoch().count();
    e.has_fix = fix.has_fix();
    e.nmea = channel.bytes();
    if (e.has_fix) {
      e.position = {fix.lat_deg, fix.lon_deg, fix.alt_msl_m};
      e.position_enu_m = to_api(frame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m}));
      e.speed_mps = fix.speed_mps;
      e.vel_up_mps = fix.vel_up_mps;
      e.satellites_used = fix.satellites_used;
      e.hdop = fix.hdop;
    } else {
      constexpr double nan = std::numeric_limits<double>::quiet_NaN();
      e.position = {nan, nan, nan};
      e.position_enu_m = {nan, nan, nan};
    }
    return e;
  }
  Epoch report(const std::optional<sources::Truth>& truth) {
    const UtcNs t = next_time();
    return report(t, channel.step(t, truth).fix);
  }
};

Receiver::Receiver(const Options& options, const std::optional<std::string>& config_file) {
  const Config config = make_config(options, config_file);
  try {
    ReceiverSetup setup = receiver_setup(config.receiver(), config.timeline);
    add_faults(setup.channel, config.timeline.faults, 0, 1);  // a config file's [[fault]] tables
    impl_ = std::make_unique<Impl>(std::move(setup), loop_settings(config.timeline));
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(e.what());
  }
}
Receiver::~Receiver() = default;
Receiver::Receiver(Receiver&&) noexcept = default;
Receiver& Receiver::operator=(Receiver&&) noexcept = default;

Epoch Receiver::step() {
  Impl& s = *impl_;
  if (!s.channel.source()) {
    if (!s.setup.sim_source) {
      throw Error("step(): source '" + s.setup.source_text +
                  "' is not a simulator scenario (sim:...); give the truth with step_enu or step_geodetic");
    }
    try {
      s.setup.check_source();
      s.channel.set_source(s.setup.make_source(s.channel.frame(), s.timeline.first_epoch()));
    } catch (const std::exception& e) {
      throw Error(e.what());
    }
  }
  const UtcNs t = s.next_time();
  return s.report(t, s.channel.step(t).fix);
}

Epoch Receiver::step_enu(const Enu& position_m, const Enu& velocity_mps) {
  return impl_->report(sources::Truth{to_internal(position_m), to_internal(velocity_mps), std::nullopt, {}});
}

Epoch Receiver::step_geodetic(const LatLonAlt& position, const Enu& velocity_mps) {
  return step_enu(to_enu(position), velocity_mps);
}

Epoch Receiver::step_no_fix() { return impl_->report(std::nullopt); }

std::string Receiver::control(const std::string& request) {
  faults::FaultControl control({&impl_->channel.faults()});
  return control.handle(request);
}

std::string control_request(const std::string& socket, const std::string& request, double timeout_s) {
  if (!(timeout_s > 0.0) || timeout_s > 3600.0) throw Error("control_request: timeout_s must be in (0, 3600]");
  try {
    return gpsemu::control_request(socket, request,
                                   std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(timeout_s * 1000.0))));
  } catch (const std::exception& e) {
    throw Error(e.what());
  }
}

std::int64_t Receiver::next_epoch_ns() const { return impl_->next_time().time_since_epoch().count(); }
double Receiver::rate_hz() const { return impl_->rate_hz; }
LatLonAlt Receiver::origin() const {
  const Geodetic& o = impl_->channel.frame().origin();
  return {o.lat_deg, o.lon_deg, o.alt_m};
}
Enu Receiver::to_enu(const LatLonAlt& p) const { return to_api(impl_->channel.frame().to_enu({p[0], p[1], p[2]})); }
LatLonAlt Receiver::to_geodetic(const Enu& p) const {
  const Geodetic g = impl_->channel.frame().to_geodetic(to_internal(p));
  return {g.lat_deg, g.lon_deg, g.alt_m};
}

std::vector<OptionInfo> option_info() {
  std::vector<OptionInfo> out;
  for (const OptionDef& o : option_table()) out.push_back({o.name, o.value_name, o.help, o.repeatable});
  return out;
}

std::string version() { return GPSEMU_VERSION; }

}  // namespace gpsemu::api
