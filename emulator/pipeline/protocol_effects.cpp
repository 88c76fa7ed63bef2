#include "emulator/pipeline/protocol_effects.hpp"

#include <chrono>
#include <cmath>
#include <utility>
#include <variant>

#include <spdlog/spdlog.h>

#include "nmea/line_budget.hpp"
#include "transport/serial_output.hpp"

namespace gpsemu {
namespace {

double ms(std::chrono::nanoseconds d) { return std::chrono::duration<double, std::milli>(d).count(); }

/// Warns when the widest epoch no longer fits the line in one epoch period.
void check_line(const Channel& channel, const ReceiverSchedule& schedule, ReceiverLine& line, const std::string& who) {
  if (line.baud == 0) return;
  const std::size_t widest = widest_epoch_bytes(channel);
  const std::size_t carried = nmea::line_bytes_per_period(line.baud, schedule.period());
  if (widest <= carried) return;
  const double rate_hz = 1e3 / ms(schedule.period());
  const int fitting = nmea::smallest_standard_baud(nmea::line_budget(widest, rate_hz));
  log_limited(line.effect_log, spdlog::level::warn, "{}{}: the widest epoch ({} bytes) does not fit the line: {} baud carries {} bytes a {} ms epoch; "
               "the TX buffer overflows and the messages that do not fit are dropped whole (counted in the summary){}",
               who, channel.protocol().name(), widest, line.baud, carried, ms(schedule.period()),
               fitting != 0 ? fmt::format("; {} baud would carry it", fitting) : std::string{});
}

void change_baud(const std::vector<std::unique_ptr<transport::Output>>& outputs, ReceiverLine& line, int baud_bps,
                 const std::string& origin, const std::string& who) {
  for (const auto& out : outputs) {
    auto* serial = out->serial_line();
    if (!serial) continue;
    std::string error_text;
    if (!serial->set_baud(baud_bps, error_text)) {
      log_limited(line.effect_log, spdlog::level::warn, "{}{}: {}", who, origin, error_text);
      continue;
    }
    log_limited(line.effect_log, spdlog::level::info, "{}{}: {} now at {} baud", who, origin,
                           serial->device(), baud_bps);
  }
  line.baud = line_of(outputs).baud;
}

void change_period(ReceiverSchedule& schedule, const protocol::PeriodChanged& changed, UtcNs t,
                   const std::string& origin, LogLimit& log, const std::string& who) {
  schedule.follow(changed.grid, t);
  if (!changed.warning.empty()) {
    log_limited(log, spdlog::level::warn, "{}{}: {}", who, origin, changed.warning);
  } else {
    log_limited(log, spdlog::level::info, "{}{}: a solution every {} ms", who, origin,
                           schedule.period().count() / 1'000'000);
  }
}

}  // namespace

std::size_t widest_epoch_bytes(const Channel& channel) {
  return channel.protocol().widest_epoch_bytes(resolve_geometry(channel.settings().receiver));
}

ReceiverLine line_of(const std::vector<std::unique_ptr<transport::Output>>& outputs) {
  ReceiverLine line;
  for (const auto& out : outputs) {
    const transport::SerialOutput* serial = std::as_const(*out).serial_line();
    if (!serial) continue;
    const auto baud = static_cast<std::uint32_t>(serial->baud_bps());
    if (line.baud == 0 || baud < line.baud) line.baud = baud;
  }
  return line;
}

void apply_protocol_effects(Channel& channel, const std::vector<std::unique_ptr<transport::Output>>& outputs,
                            ReceiverSchedule& schedule, ReceiverLine& line, UtcNs t, const std::string& who) {
  bool recheck = false;
  for (const protocol::Effect& effect : channel.protocol().take_effects()) {
    if (const auto* period = std::get_if<protocol::PeriodChanged>(&effect.what)) {
      change_period(schedule, *period, t, effect.origin, line.effect_log, who);
      recheck = true;
    } else if (const auto* baud = std::get_if<protocol::BaudChanged>(&effect.what)) {
      change_baud(outputs, line, static_cast<int>(baud->baud_bps), effect.origin, who);
      recheck = true;
    } else if (std::holds_alternative<protocol::ColdStart>(effect.what)) {
      log_limited(line.effect_log, spdlog::level::info, "{}{}: cold start", who, effect.origin);
      channel.cold_start(t);
    }
  }
  if (recheck) check_line(channel, schedule, line, who);
}

void fit_epoch_to_line(Channel& channel, std::chrono::nanoseconds period, ReceiverLine& line, const std::string& who) {
  if (line.baud == 0) return;
  const std::size_t carried = nmea::line_bytes_per_period(line.baud, period);
  const protocol::LineDrops drops = channel.protocol().fit_to_line(channel.bytes(), carried);
  if (drops.messages == 0) return;
  line.dropped.messages += drops.messages;
  line.dropped.bytes += drops.bytes;
  log_limited(line.tx_drop_log, spdlog::level::warn,
                         "{}{} TX buffer overflow: {} message(s) ({} bytes) dropped so far: {} baud carries {} "
                         "bytes a {} ms epoch",
                         who, channel.protocol().name(), line.dropped.messages, line.dropped.bytes, line.baud, carried,
                         ms(period));
}

std::string client_input_summary(const Channel& channel) {
  std::string rover;
  if (channel.settings().moving_base.role == heading::Role::rover) {
    rover = fmt::format("; {} of the RTCM3 frames the moving base's (4072.0)", channel.moving_base_frames());
  }
  return channel.protocol().client_input_summary(rover);
}

std::string tx_drops_summary(const Channel& channel, const ReceiverLine& line) {
  if (line.dropped.messages == 0) return {};
  return fmt::format("{} TX buffer: {} messages ({} bytes) dropped, the line at {} baud could not carry them",
                     channel.protocol().name(), line.dropped.messages, line.dropped.bytes, line.baud);
}

}  // namespace gpsemu
