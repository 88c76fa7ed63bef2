#include "emulator/pipeline/pps_timeline.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "transport/gpio_pps.hpp"
#include "transport/modem_pps.hpp"

namespace gpsemu {

std::unique_ptr<transport::PpsLine> open_pps(const PpsSettings& settings, const Sink& sink) {
  const transport::PpsSpec& spec = settings.spec.value();
  const auto polarity = settings.active_low ? transport::PpsPolarity::active_low : transport::PpsPolarity::active_high;
  if (spec.kind == transport::PpsSpec::Kind::gpio) return std::make_unique<transport::GpioPps>(spec.chip, spec.line, polarity);
  if (transport::SerialOutput* serial = sink.first_serial()) {
    return std::make_unique<transport::ModemPps>(*serial, spec.modem_line, polarity);
  }
  throw std::runtime_error(fmt::format(
      "--pps {}: drives a modem line of the serial output, but there is no serial output: add --output "
      "serial:DEVICE[@BAUD] (a pty output has no modem lines; with one, use --pps gpio:CHIP:LINE)",
      transport::to_string(spec)));
}

void PpsTimeline::start(UtcNs first_wall) { next_edge_ = {std::chrono::ceil<std::chrono::seconds>(first_wall), true}; }

void PpsTimeline::run_until(UtcNs wall_deadline, ClockIo& io, const std::atomic<bool>& stop,
                            const std::function<bool()>* woken) {
  while (!stop.load() && next_edge_.time <= wall_deadline) {
    if (woken) {
      io.sleep_until_woken(next_edge_.time, stop, *woken);
      if (!stop.load() && (*woken)()) return;
    } else {
      io.sleep_until(next_edge_.time, stop);
    }
    if (stop.load()) return;
    if (io.now() < next_edge_.time) return;  // the wall clock was set: the loop looks again
    const transport::PpsEdge edge = next_edge_;
    next_edge_ = transport::next_pps_edge(edge, width_);
    const auto late = io.now() - edge.time;
    if (edge.leading && late > width_ / 2) {
      // A pulse that late would mark the wrong instant: skip it (and its trailing edge).
      ++stats_.pulses_late_skipped;
      next_edge_ = transport::next_pps_edge(next_edge_, width_);
      log_limited(skip_log_, spdlog::level::warn, "PPS pulse of {} skipped: {} ms late",
                             format_iso8601_utc(edge.time + shift_),
                             std::chrono::duration_cast<std::chrono::milliseconds>(late).count());
      continue;
    }
    if (line_.set(edge.leading) && edge.leading) {
      ++stats_.pulses;
      stats_.worst_edge_delay = std::max(stats_.worst_edge_delay, io.now() - edge.time);
    }
  }
}

void PpsTimeline::finish(ClockIo& io, const std::atomic<bool>& stop) {
  if (!line_.pulse_on()) return;
  if (!stop.load()) io.sleep_until(next_edge_.time, stop);
  line_.set(false);
}

void PpsTimeline::log_opened() const {
  spdlog::info("PPS on {}: leading edge at each whole UTC second, {} ms wide, {}", line_.describe(),
               std::chrono::duration<double, std::milli>(width_).count(),
               line_.polarity() == transport::PpsPolarity::active_high ? "high during the pulse" : "low during the pulse");
}

void PpsTimeline::log_summary() const {
  spdlog::info("PPS {}: {} pulses, {} skipped late, {} edges failed; worst leading edge {:.3f} ms after its second",
               line_.describe(), stats_.pulses, stats_.pulses_late_skipped, line_.stats().failures,
               std::chrono::duration<double, std::milli>(stats_.worst_edge_delay).count());
}

}  // namespace gpsemu
