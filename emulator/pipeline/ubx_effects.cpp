#include "emulator/pipeline/ubx_effects.hpp"

#include <chrono>
#include <cmath>
#include <variant>

#include <spdlog/spdlog.h>

#include "emulator/pipeline/serial_line_check.hpp"
#include "emulator/ubx/output.hpp"
#include "emulator/ubx/solution_grid.hpp"
#include "nmea/line_budget.hpp"
#include "transport/serial_output.hpp"

namespace gpsemu {
namespace {

double ms(std::chrono::nanoseconds d) { return std::chrono::duration<double, std::milli>(d).count(); }

/// Warns when the widest epoch no longer fits the line in one epoch period.
void check_line(const Channel& channel, const ReceiverSchedule& schedule, UbxLine& line, const std::string& who) {
  if (line.baud == 0) return;
  const std::size_t widest = widest_ubx_epoch_bytes(channel);
  const std::size_t carried = ubx::line_bytes_per_period(line.baud, schedule.period());
  if (widest <= carried) return;
  const double rate_hz = 1e3 / ms(schedule.period());
  const int fitting = nmea::smallest_standard_baud(nmea::line_budget(widest, rate_hz));
  transport::log_limited(line.effect_log, spdlog::level::warn, "{}u-blox: the widest epoch ({} bytes) does not fit the line: {} baud carries {} bytes a {} ms epoch; "
               "the TX buffer overflows and the messages that do not fit are dropped whole (counted in the summary){}",
               who, widest, line.baud, carried, ms(schedule.period()),
               fitting != 0 ? fmt::format("; {} baud would carry it", fitting) : std::string{});
}

void change_baud(const std::vector<std::unique_ptr<transport::Output>>& outputs, UbxLine& line, int baud_bps,
                 const std::string& who) {
  for (const auto& out : outputs) {
    auto* serial = dynamic_cast<transport::SerialOutput*>(out.get());
    if (!serial) continue;
    std::string error_text;
    if (!serial->set_baud(baud_bps, error_text)) {
      transport::log_limited(line.effect_log, spdlog::level::warn, "{}u-blox CFG-PRT: {}", who, error_text);
      continue;
    }
    transport::log_limited(line.effect_log, spdlog::level::info, "{}u-blox CFG-PRT: {} now at {} baud", who,
                           serial->device(), baud_bps);
  }
  line.baud = ubx_line_of(outputs).baud;
}

void change_period(const Channel& channel, ReceiverSchedule& schedule, std::chrono::milliseconds asked, UtcNs t,
                   transport::LogLimit& log, const std::string& who) {
  const ubx::Session& session = channel.ubx_encoder()->session();
  const ubx::ConfigMachine& machine = session.machine();
  const bool start_period = asked == channel.settings().ubx->start.measurement_period;
  const ubx::SolutionGrid grid = ubx::solution_grid(machine.settings(), machine.model());
  schedule.follow(start_period ? std::nullopt : std::optional<ubx::SolutionGrid>{grid}, t);
  if (!start_period && grid.period != asked) {
    transport::log_limited(log, spdlog::level::warn, "{}u-blox CFG-RATE: a solution every {} ms asked (acknowledged, as the receiver does), but a {} "
                 "navigates at most every {} ms: solutions every {} ms",
                 who, asked.count(), ubx::model_info(machine.model()).name, grid.period.count(), grid.period.count());
  } else {
    transport::log_limited(log, spdlog::level::info, "{}u-blox CFG-RATE: a solution every {} ms", who,
                           schedule.period().count() / 1'000'000);
  }
}

}  // namespace

std::size_t widest_ubx_epoch_bytes(const nmea::FormatOptions& format, const ubx::Settings& settings, ubx::Port port,
                                   ubx::ReceiverModel model, const Geometry& sky) {
  nmea::FormatOptions nmea_part = format;
  nmea_part.sentences = {};
  for (const nmea::SentenceType type : nmea::all_sentence_types) {
    const auto id = ubx::nmea_message(type);
    if (id && settings.rate(*id, port) > 0) nmea_part.sentences.insert(type);
  }
  const std::size_t nmea_bytes = nmea_part.sentences.empty() ? 0 : worst_case_epoch_bytes(nmea_part, sky.in_view_by_system, sky.satellites_used);
  return nmea_bytes + ubx::widest_solution_ubx_bytes(settings, port, model);
}

std::size_t widest_ubx_epoch_bytes(const Channel& channel) {
  const UbxEncoder* ubx = channel.ubx_encoder();
  if (!ubx) return 0;
  const ubx::ConfigMachine& machine = ubx->session().machine();
  return widest_ubx_epoch_bytes(channel.settings().format, machine.settings(), machine.port(), machine.model(),
                                resolve_geometry(channel.settings().receiver));
}

UbxLine ubx_line_of(const std::vector<std::unique_ptr<transport::Output>>& outputs) {
  UbxLine line;
  for (const auto& out : outputs) {
    const auto* serial = dynamic_cast<const transport::SerialOutput*>(out.get());
    if (!serial) continue;
    const auto baud = static_cast<std::uint32_t>(serial->baud_bps());
    if (line.baud == 0 || baud < line.baud) line.baud = baud;
  }
  return line;
}

void apply_ubx_effects(Channel& channel, const std::vector<std::unique_ptr<transport::Output>>& outputs,
                       ReceiverSchedule& schedule, UbxLine& line, UtcNs t, const std::string& who) {
  UbxEncoder* ubx = channel.ubx_encoder();
  if (!ubx) return;
  bool recheck = false;
  for (const ubx::Effect& effect : ubx->take_effects()) {
    if (const auto* rate = std::get_if<ubx::MeasurementPeriodChanged>(&effect)) {
      change_period(channel, schedule, rate->period, t, line.effect_log, who);
      recheck = true;
    } else if (const auto* baud = std::get_if<ubx::BaudChanged>(&effect)) {
      change_baud(outputs, line, static_cast<int>(baud->baud), who);
      recheck = true;
    } else if (std::holds_alternative<ubx::ColdStart>(effect)) {
      transport::log_limited(line.effect_log, spdlog::level::info, "{}u-blox CFG-RST: cold start", who);
      channel.cold_start(t);
    }
  }
  if (recheck) check_line(channel, schedule, line, who);
}

void fit_epoch_to_line(Channel& channel, std::chrono::nanoseconds period, UbxLine& line, const std::string& who) {
  if (line.baud == 0) return;
  const ubx::TxDrops drops = ubx::fit_epoch_to_line(channel.bytes(), ubx::line_bytes_per_period(line.baud, period));
  if (drops.messages == 0) return;
  line.dropped.messages += drops.messages;
  line.dropped.bytes += drops.bytes;
  transport::log_limited(line.tx_drop_log, spdlog::level::warn,
                             "{}u-blox TX buffer overflow: {} message(s) ({} bytes) dropped so far: {} baud carries {} "
                             "bytes a {} ms epoch",
                             who, line.dropped.messages, line.dropped.bytes, line.baud,
                             ubx::line_bytes_per_period(line.baud, period), ms(period));
}

std::string client_input_summary(const Channel& channel) {
  const UbxEncoder* ubx = channel.ubx_encoder();
  if (!ubx) return {};
  const ubx::FrameStats& in = ubx->session().reader_stats();
  const ubx::MachineStats& answered = ubx->session().machine().stats();
  const ubx::SessionStats& folded = ubx->session().stats();
  std::string rtcm3;
  if (channel.settings().moving_base.role == heading::Role::rover) {
    rtcm3 = fmt::format("; {} of the RTCM3 frames the moving base's (4072.0)", channel.moving_base_frames());
  }
  // Why they were ignored: a model without RTCM3 input (the M10), or the port's input protocols.
  const ubx::ReceiverModel model = ubx->session().machine().model();
  const std::string why = ubx::model_info(model).rtcm_input
                              ? std::string{"the port's input protocols exclude RTCM3"}
                              : fmt::format("{} takes no RTCM3", ubx::model_info(model).name);
  const std::string rtcm_ignored =
      folded.rtcm_ignored == 0 ? std::string{} : fmt::format(", {} ignored: {}", folded.rtcm_ignored, why);
  return fmt::format("u-blox client input: {} UBX frames, {} bad ({} bad checksum, {} too long), {} NMEA sentences "
                     "({} bad), {} RTCM3 frames ({} bad CRC{}), {} garbage bytes; {} ACK, {} NAK, {} ignored; {} NAV "
                     "polls folded into one answer, {} effects superseded by a newer one{}{}",
                     in.frames_ok, in.bad_checksum + in.too_long, in.bad_checksum, in.too_long, in.sentences_ok,
                     in.bad_sentences, in.rtcm_ok, in.rtcm_bad_crc, rtcm_ignored, in.garbage_bytes, answered.acks, answered.naks,
                     answered.ignored, folded.polls_merged, folded.effects_superseded, rtcm3,
                     answered.last_nak.empty() ? std::string{} : fmt::format("; last NAK {}", answered.last_nak));
}

std::string ubx_config_summary(const Channel& channel) {
  const UbxEncoder* ubx = channel.ubx_encoder();
  if (!ubx) return {};
  const ubx::MachineStats& s = ubx->session().machine().stats();
  if (s.unsent_answers == 0 && s.transactions_discarded == 0 && s.resets == 0) return {};
  return fmt::format("u-blox configuration: {} UBX answers not sent (the port's output protocols excluded UBX), {} "
                     "CFG-VALSET transactions discarded unapplied, {} resets reloaded RAM from the layers",
                     s.unsent_answers, s.transactions_discarded, s.resets);
}

std::string tx_drops_summary(const UbxLine& line) {
  if (line.dropped.messages == 0) return {};
  return fmt::format("u-blox TX buffer: {} messages ({} bytes) dropped, the line at {} baud could not carry them",
                     line.dropped.messages, line.dropped.bytes, line.baud);
}

}  // namespace gpsemu
