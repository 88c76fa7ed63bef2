// The u-blox port behind the receiver protocol interface (see ublox_protocol.hpp).
#include "emulator/protocol/ublox/ublox_protocol.hpp"

#include <variant>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "emulator/protocol/ublox/state_file.hpp"
#include "emulator/ubx/messages.hpp"
#include "emulator/ubx/output.hpp"
#include "emulator/ubx/solution_grid.hpp"
#include "emulator/ubx/tx_budget.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu::protocol {

UbloxProtocol::UbloxProtocol(ubx::SessionSettings settings, std::optional<StateFile> state_file)
    : session_(settings), format_(std::move(settings.format)), start_period_(settings.start.measurement_period),
      nmea_on_at_start_(!settings.start.sentences.empty()), state_file_(std::move(state_file)),
      saved_version_(session_.machine().stored_version()) {}

std::string UbloxProtocol::receiver_name() const {
  return fmt::format("u-blox {}", ubx::model_info(session_.machine().model()).name);
}

std::size_t UbloxProtocol::widest_epoch_bytes(const Geometry& sky) const {
  const ubx::ConfigMachine& machine = session_.machine();
  return widest_ublox_epoch_bytes(format_, machine.settings(), machine.port(), machine.model(), sky);
}

void UbloxProtocol::save_state() {
  const ubx::ConfigMachine& machine = session_.machine();
  if (!state_file_ || machine.stored_version() == saved_version_) return;
  saved_version_ = machine.stored_version();
  std::string error;
  if (write_receiver_state(*state_file_, machine.stored(), machine.model(), error)) {
    if (state_error_reported_) spdlog::info("u-blox: --receiver-state {} written again", state_file_->path);
    state_error_reported_ = false;
  } else if (!state_error_reported_) {  // once until a write succeeds again
    spdlog::warn("u-blox: --receiver-state: {}; the stored configuration is kept in memory only", error);
    state_error_reported_ = true;
  }
}

void UbloxProtocol::client_wrote(std::string_view bytes, ClientId client) {
  session_.client_wrote(bytes, client);
  save_state();
  report_dropped_answers();
  const ubx::FrameStats& stats = session_.reader_stats();
  const std::uint64_t bad = stats.bad_checksum + stats.too_long + stats.rtcm_bad_crc;
  if (bad == bad_frames_reported_ || !bad_frame_log_.admit(LogLimit::Clock::now())) return;
  (void)bad_frame_log_.take_suppressed();  // the line counts the frames themselves
  spdlog::warn("u-blox: {} bad frame(s) from the client ({} UBX bad checksum, {} UBX too long, {} RTCM3 bad CRC in all)",
               bad - bad_frames_reported_, stats.bad_checksum, stats.too_long, stats.rtcm_bad_crc);
  bad_frames_reported_ = bad;
}

void UbloxProtocol::report_dropped_answers() {
  const ubx::SessionStats& stats = session_.stats();
  if (stats.answers_dropped == answers_dropped_reported_) return;
  if (log_limited(answer_drop_log_, spdlog::level::warn,
                             "u-blox: {} answer(s) dropped whole, more than {} bytes of answers waited for their client "
                             "({} in all)",
                             stats.answers_dropped - answers_dropped_reported_, ubx::Session::max_reply_bytes,
                             stats.answers_dropped)) {
    answers_dropped_reported_ = stats.answers_dropped;
  }
}

std::vector<Effect> UbloxProtocol::take_effects() {
  std::vector<Effect> out;
  for (const ubx::Effect& effect : session_.take_effects()) {
    if (const auto* rate = std::get_if<ubx::MeasurementPeriodChanged>(&effect)) {
      // The solution grid of the settings now: the run's grid again for the start period.
      const ubx::ConfigMachine& machine = session_.machine();
      PeriodChanged changed;
      if (rate->period != start_period_) {
        const ubx::SolutionGrid grid = ubx::solution_grid(machine.settings(), machine.model());
        changed.grid = SolutionGrid{grid.period, [grid](UtcNs t) { return grid.next_after(t); }};
        if (grid.period != rate->period) {
          changed.warning = fmt::format("a solution every {} ms asked (acknowledged, as the receiver does), but a {} "
                                        "navigates at most every {} ms: solutions every {} ms",
                                        rate->period.count(), ubx::model_info(machine.model()).name,
                                        grid.period.count(), grid.period.count());
        }
      }
      out.push_back({"u-blox CFG-RATE", std::move(changed)});
    } else if (const auto* baud = std::get_if<ubx::BaudChanged>(&effect)) {
      out.push_back({"u-blox CFG-PRT", BaudChanged{baud->baud}});
    } else if (std::holds_alternative<ubx::ColdStart>(effect)) {
      out.push_back({"u-blox CFG-RST", ColdStart{}});
    }
  }
  return out;
}

void UbloxProtocol::reset(ResetKind kind) {
  switch (kind) {
    case ResetKind::hardware_cold:
      // RAM reloaded from BBR, flash and the defaults, the receiver's own state (msss, TTFF, time
      // validity) starts again; the period and baud effects follow at the next epoch.
      session_.hardware_reset();
      break;
  }
}

LineDrops UbloxProtocol::fit_to_line(std::string& epoch, std::size_t budget_bytes) {
  const ubx::TxDrops drops = ubx::fit_epoch_to_line(epoch, budget_bytes);
  return {drops.messages, drops.bytes};
}

std::string UbloxProtocol::client_input_summary(std::string_view extra) const {
  const ubx::FrameStats& in = session_.reader_stats();
  const ubx::MachineStats& answered = session_.machine().stats();
  const ubx::SessionStats& folded = session_.stats();
  // Why they were ignored: a model without RTCM3 input (the M10), or the port's input protocols.
  const ReceiverModel model = session_.machine().model();
  const std::string why = ubx::model_info(model).rtcm_input
                              ? std::string{"the port's input protocols exclude RTCM3"}
                              : fmt::format("{} takes no RTCM3", ubx::model_info(model).name);
  const std::string rtcm_ignored =
      folded.rtcm_ignored == 0 ? std::string{} : fmt::format(", {} ignored: {}", folded.rtcm_ignored, why);
  return fmt::format("u-blox client input: {} UBX frames, {} bad ({} bad checksum, {} too long), {} NMEA sentences "
                     "({} bad), {} RTCM3 frames ({} bad CRC{}), {} garbage bytes; {} ACK, {} NAK, {} ignored; {} NAV "
                     "polls folded into one answer, {} effects superseded by a newer one{}{}",
                     in.frames_ok, in.bad_checksum + in.too_long, in.bad_checksum, in.too_long, in.sentences_ok,
                     in.bad_sentences, in.rtcm_ok, in.rtcm_bad_crc, rtcm_ignored, in.garbage_bytes, answered.acks,
                     answered.naks, answered.ignored, folded.polls_merged, folded.effects_superseded, extra,
                     answered.last_nak.empty() ? std::string{} : fmt::format("; last NAK {}", answered.last_nak));
}

namespace {

/// "NAV-PVT"; an NMEA message by its sentence ("GGA").
std::string panel_name(ubx::MessageId id) {
  constexpr std::string_view kNmea = "NMEA-";
  std::string name = ubx::message_name(id);
  return name.rfind(kNmea, 0) == 0 ? name.substr(kNmea.size()) : name;
}

}  // namespace

std::string UbloxProtocol::configuration_json() const {
  const ubx::ConfigMachine& m = session_.machine();
  const ubx::Settings& s = m.settings();
  const auto port = static_cast<std::size_t>(m.port());
  nlohmann::json enabled = nlohmann::json::array();
  for (const auto& [id, rates] : s.rates) {
    if (rates[port] != 0) enabled.push_back({{"message", panel_name(id)}, {"rate", rates[port]}});
  }
  const ubx::MachineStats& st = m.stats();
  const ubx::FrameStats& in = session_.reader_stats();
  const int period_ms = std::max(1, s.meas_period_ms * s.nav_rate_cycles);
  return nlohmann::json{{"frames_received", in.frames_ok},
                        {"sentences_received", in.sentences_ok},
                        {"bad_frames", in.bad_checksum + in.too_long + in.bad_sentences},
                        {"acks", st.acks},
                        {"naks", st.naks},
                        {"ignored", st.ignored},
                        {"resets", st.resets},
                        {"meas_period_ms", s.meas_period_ms},
                        {"nav_rate_cycles", s.nav_rate_cycles},
                        {"solution_hz", std::round(1000.0 / period_ms * 1000.0) / 1000.0},
                        {"port_baud", s.ports[port].baud},
                        {"enabled", enabled}}
      .dump();
}

std::string UbloxProtocol::configuration_summary() const {
  const ubx::MachineStats& s = session_.machine().stats();
  if (s.unsent_answers == 0 && s.transactions_discarded == 0 && s.resets == 0) return {};
  return fmt::format("u-blox configuration: {} UBX answers not sent (the port's output protocols excluded UBX), {} "
                     "CFG-VALSET transactions discarded unapplied, {} resets reloaded RAM from the layers",
                     s.unsent_answers, s.transactions_discarded, s.resets);
}

std::size_t widest_ublox_epoch_bytes(const nmea::FormatOptions& format, const ubx::Settings& settings, ubx::Port port,
                                     ReceiverModel model, const Geometry& sky) {
  nmea::FormatOptions nmea_part = format;
  nmea_part.sentences = {};
  for (const nmea::SentenceType type : nmea::all_sentence_types) {
    const auto id = ubx::nmea_message(type);
    if (id && settings.rate(*id, port) > 0) nmea_part.sentences.insert(type);
  }
  const std::size_t nmea_bytes =
      nmea_part.sentences.empty()
          ? 0
          : nmea::line_budget(nmea_part, sky.in_view_by_system, sky.satellites_used, 1.0).bytes_per_epoch;
  return nmea_bytes + ubx::widest_solution_ubx_bytes(settings, port, model);
}

namespace {

class UbloxSpec final : public ProtocolSpec {
 public:
  UbloxSpec(ubx::SessionSettings settings, std::optional<StateFile> state_file)
      : settings_(std::move(settings)), state_file_(std::move(state_file)) {}
  [[nodiscard]] std::unique_ptr<ReceiverProtocol> make() const override {
    return std::make_unique<UbloxProtocol>(settings_, state_file_);
  }
  [[nodiscard]] std::size_t widest_epoch_bytes(const Geometry& sky) const override {
    return widest_ublox_epoch_bytes(settings_.format, ubx::start_settings(settings_.start), settings_.start.port,
                                    settings_.start.model, sky);
  }
  [[nodiscard]] bool client_may_change_period() const override { return true; }

 private:
  ubx::SessionSettings settings_;
  std::optional<StateFile> state_file_;
};

}  // namespace

std::shared_ptr<const ProtocolSpec> ublox_protocol(ubx::SessionSettings settings,
                                                   std::optional<StateFile> state_file) {
  return std::make_shared<UbloxSpec>(std::move(settings), std::move(state_file));
}

}  // namespace gpsemu::protocol
