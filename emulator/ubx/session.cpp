// One u-blox port (see session.hpp).
#include "emulator/ubx/session.hpp"

#include <utility>

#include "emulator/ubx/output.hpp"
#include "emulator/ubx/solution_grid.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::ubx {

Session::Session(SessionSettings settings)
    : settings_(std::move(settings)), machine_(settings_.start), state_(settings_.seed) {}

void Session::client_wrote(std::string_view bytes) {
  Answer answer = machine_.feed(bytes);
  reply_ += answer.bytes;
  for (Effect& effect : answer.effects) {
    if (const auto* poll = std::get_if<PollOnce>(&effect)) {
      polled_.push_back(poll->id);
    } else if (std::holds_alternative<MeasurementPeriodChanged>(effect) || std::holds_alternative<BaudChanged>(effect) ||
               std::holds_alternative<ColdStart>(effect)) {
      if (std::holds_alternative<ColdStart>(effect)) state_.restart();
      effects_.push_back(std::move(effect));
    }
    // Rates, sentences and protocols are in the settings append_solution() reads.
  }
}

bool Session::on_solution_grid(nmea::UtcTime t) const {
  if (machine_.settings().output_period() == settings_.start.measurement_period) return true;
  return solution_grid(machine_.settings(), machine_.model()).contains(t);
}

std::string Session::take_reply() { return std::exchange(reply_, std::string{}); }

std::vector<Effect> Session::take_effects() { return std::exchange(effects_, std::vector<Effect>{}); }

void Session::append_solution(const nmea::Fix& fix, std::string& out) {
  if (!on_solution_grid(fix.time_utc)) return;
  const ReceiverState::AtSolution now = state_.at(fix);
  NavExtras extras;
  extras.speed_sigma_mps = settings_.speed_sigma_mps;
  extras.since_start = now.since_start;
  extras.time_to_first_fix = now.time_to_first_fix;
  extras.model = machine_.model();
  extras.time = now.time;
  extras.clock = now.clock;
  extras.rf = state_.rf();

  const Settings& s = machine_.settings();
  const Port port = machine_.port();
  nmea::FormatOptions format = settings_.format;
  format.sentences = due_sentences(s, port, solutions_);
  ubx::append_solution(out, s, port, solutions_, fix, extras, polled_);
  nmea::append_epoch(fix, format, out);
  ubx::append_end_of_epoch(out, s, port, solutions_, fix, polled_);
  polled_.clear();
  ++solutions_;
}

}  // namespace gpsemu::ubx
