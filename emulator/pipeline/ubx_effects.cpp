#include "emulator/pipeline/ubx_effects.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <variant>

#include <spdlog/spdlog.h>

#include "emulator/pipeline/serial_line_check.hpp"
#include "emulator/ubx/output.hpp"
#include "transport/serial_output.hpp"

namespace gpsemu {
namespace {

void change_baud(const Channel& channel, const std::vector<std::unique_ptr<transport::Output>>& outputs,
                 double loop_rate_hz, int baud_bps, const std::string& who) {
  const ubx::ConfigMachine& machine = channel.ubx_encoder()->session().machine();
  for (const auto& out : outputs) {
    auto* serial = dynamic_cast<transport::SerialOutput*>(out.get());
    if (!serial) continue;
    std::string error_text;
    if (!serial->set_baud(baud_bps, error_text)) {
      spdlog::warn("{}u-blox CFG-PRT: {}", who, error_text);
      continue;
    }
    spdlog::info("{}u-blox CFG-PRT: {} now at {} baud", who, serial->device(), baud_bps);
    try {
      transport::OutputSpec spec{.kind = transport::OutputKind::serial, .path = serial->device(), .baud_bps = baud_bps};
      check_serial_line_budget(spec, widest_ubx_epoch_bytes(channel.settings().format, machine.settings(), machine.port()),
                               loop_rate_hz);
    } catch (const std::exception& e) {
      spdlog::warn("{}u-blox CFG-PRT: {}", who, e.what());
    }
  }
}

void change_period(std::chrono::milliseconds period, double loop_rate_hz, const std::string& who) {
  const auto loop_ms = std::llround(1000.0 / loop_rate_hz);
  if (period.count() >= loop_ms && period.count() % loop_ms == 0) return;  // the session's grid thins the loop's
  spdlog::warn("{}u-blox CFG-RATE: a solution every {} ms asked, but epochs come every {} ms (--rate {}): the "
               "solutions stay on that grid; start with a --rate whose period divides {} ms",
               who, period.count(), loop_ms, loop_rate_hz, period.count());
}

}  // namespace

std::size_t widest_ubx_epoch_bytes(const nmea::FormatOptions& format, const ubx::Settings& settings, ubx::Port port) {
  nmea::FormatOptions nmea_part = format;
  nmea_part.sentences = {};
  for (const nmea::SentenceType type : nmea::all_sentence_types) {
    if (settings.rate(ubx::nmea_message(type), port) > 0) nmea_part.sentences.insert(type);
  }
  const std::size_t nmea_bytes = nmea_part.sentences.empty() ? 0 : worst_case_epoch_bytes(nmea_part);
  return nmea_bytes + ubx::widest_solution_ubx_bytes(settings, port);
}

void apply_ubx_effects(Channel& channel, const std::vector<std::unique_ptr<transport::Output>>& outputs,
                       double loop_rate_hz, UtcNs t, const std::string& who) {
  UbxEncoder* ubx = channel.ubx_encoder();
  if (!ubx) return;
  for (const ubx::Effect& effect : ubx->take_effects()) {
    if (const auto* rate = std::get_if<ubx::MeasurementPeriodChanged>(&effect)) {
      change_period(rate->period, loop_rate_hz, who);
    } else if (const auto* baud = std::get_if<ubx::BaudChanged>(&effect)) {
      change_baud(channel, outputs, loop_rate_hz, static_cast<int>(baud->baud), who);
    } else if (std::holds_alternative<ubx::ColdStart>(effect)) {
      spdlog::info("{}u-blox CFG-RST: cold start", who);
      channel.cold_start(t);
    }
  }
}

}  // namespace gpsemu
