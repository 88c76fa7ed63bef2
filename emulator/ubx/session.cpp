// One u-blox port (see session.hpp).
#include "emulator/ubx/session.hpp"

#include <algorithm>
#include <utility>

#include "emulator/ubx/output.hpp"
#include "emulator/ubx/solution_grid.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::ubx {

Session::Session(SessionSettings settings)
    : settings_(std::move(settings)), machine_(settings_.start, settings_.stored) {
  // What the stored layers changed at power-up reaches the emulator as a client's change would.
  const Settings& now = machine_.settings();
  const Settings& start = machine_.defaults();
  if (now.output_period() != start.output_period()) effects_.emplace_back(MeasurementPeriodChanged{now.output_period()});
  const auto port = static_cast<std::size_t>(machine_.port());
  if (now.ports[port].baud != start.ports[port].baud && now.ports[port].baud != 0) {
    effects_.emplace_back(BaudChanged{now.ports[port].baud});
  }
}

bool Session::period_change_pending() const {
  return std::any_of(effects_.begin(), effects_.end(),
                     [](const Effect& e) { return std::holds_alternative<MeasurementPeriodChanged>(e); });
}

void Session::client_wrote(std::string_view bytes) {
  Answer answer = machine_.feed(bytes);
  reply_ += answer.bytes;
  for (Effect& effect : answer.effects) {
    if (const auto* poll = std::get_if<PollOnce>(&effect)) {
      polled_.push_back(poll->id);
    } else if (std::holds_alternative<MeasurementPeriodChanged>(effect) || std::holds_alternative<BaudChanged>(effect) ||
               std::holds_alternative<ColdStart>(effect)) {
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
  if (!first_epoch_) first_epoch_ = fix.time_utc;
  NavExtras extras;
  extras.speed_sigma_mps = settings_.speed_sigma_mps;
  extras.since_start = fix.time_utc - *first_epoch_;
  if (!time_to_first_fix_ && fix.has_fix()) time_to_first_fix_ = extras.since_start;
  extras.time_to_first_fix = time_to_first_fix_.value_or(std::chrono::milliseconds{0});

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
