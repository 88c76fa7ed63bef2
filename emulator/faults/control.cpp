#include "emulator/faults/control.hpp"

#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "emulator/faults/json_shape.hpp"

namespace gpsemu::faults {
namespace {

using nlohmann::json;

/// The receivers a message names: "receiver" an index or "all" (absent: all).
std::vector<std::size_t> receivers_of(const json& message, std::size_t count) {
  std::vector<std::size_t> out;
  const auto it = message.find("receiver");
  if (it == message.end() || (it->is_string() && it->get<std::string>() == "all")) {
    for (std::size_t i = 0; i < count; ++i) out.push_back(i);
    return out;
  }
  if (!it->is_number_integer() || it->get<std::int64_t>() < 0 || static_cast<std::uint64_t>(it->get<std::int64_t>()) >= count)
    throw std::invalid_argument(fmt::format("receiver: expected an index 0..{} or \"all\", got {}", count - 1, it->dump()));
  out.push_back(static_cast<std::size_t>(it->get<std::int64_t>()));
  return out;
}

json receivers_json(const std::vector<std::size_t>& receivers) {
  json a = json::array();
  for (const std::size_t i : receivers) a.push_back(i);
  return a;
}

/// The request as the --tee file records it: for receiver `i`, without the fields it ignored.
std::string recorded(const json& message, std::size_t i) {
  json out = json::object();
  for (const auto& [key, value] : message.items()) {
    if (key == "receiver") continue;
    if (key != "fault" && key != "clear" && !value.is_number() && !value.is_string()) continue;
    out[key] = value;
  }
  out["receiver"] = i;
  return out.dump();
}

/// The epoch a request came after: it applies at the next one (the first receiver's, for a fleet).
void add_last_epoch(json& answer, const FaultTimeline& t) {
  const FaultTimeline::LastEpoch& last = t.last_epoch();
  answer["after_epoch_s"] = last.epochs ? json(last.since_s) : json(nullptr);
}

/// "jam db=25 for 10 s", "jam db=25 until cleared where circle:...": a live fault as answered.
std::string live_description(const Fault& fault) {
  std::string what = fault.parameters() + (fault.duration_s ? fmt::format(" for {:.6g} s", *fault.duration_s)
                                                            : std::string(" until cleared"));
  if (fault.where) what += " where " + fault.where->text();
  return what;
}

/// The spoof acting on `t` (or starting at its next epoch) that a clear does not end, if any.
std::optional<std::string> spoof_on(const FaultTimeline& t) {
  for (const Fault& p : t.pending()) {
    if (p.is<Spoof>()) return live_description(p);
  }
  if (t.clear_pending(FaultKind::spoof)) return std::nullopt;
  for (const FaultTimeline::Entry& e : t.entries()) {
    if (e.fault.is<Spoof>() && !e.ended && !e.cleared && (e.active || e.fading_from_s)) return e.fault.describe();
  }
  return std::nullopt;
}

/// A spoof of `t`'s scenario still to start (or an area's, armed) while the live spoof `live` would
/// be on, from the next epoch to its end (its ramp_out_s included; none: until cleared): the
/// refusal's message for receiver `i`, if any.
std::optional<std::string> spoof_ahead(std::size_t i, const FaultTimeline& t, const Fault& live) {
  if (t.clear_pending(FaultKind::spoof)) return std::nullopt;
  constexpr double kForever = std::numeric_limits<double>::infinity();
  const double now_s = t.last_epoch().since_s;
  const double live_end_s = live.duration_s && !live.where ? now_s + *live.duration_s + live.ramp_out_s : kForever;
  for (const FaultTimeline::Entry& e : t.entries()) {
    const Fault& f = e.fault;
    if (!f.is<Spoof>() || e.ended || e.cleared || e.active || e.fading_from_s) continue;
    const double end_s = f.duration_s && !f.where ? f.at_s + *f.duration_s + f.ramp_out_s : kForever;
    if (f.at_s >= live_end_s || end_s <= now_s) continue;
    std::string what = fmt::format("spoof: receiver {} has {} from {:g} s", i,
                                   f.where ? "an area's spoof armed" : "a spoof scheduled", f.at_s);
    if (!f.origin.file.empty()) what += fmt::format(" ({}:{})", f.origin.file, f.origin.table_line);
    what += ": two spoofers would add their drags; ";
    if (f.where || f.at_s - now_s - live.ramp_out_s <= 0.0) return what + "clear spoof first";
    return what + fmt::format("give a duration under {:g} s, or clear spoof first", f.at_s - now_s - live.ramp_out_s);
  }
  return std::nullopt;
}

std::string fault_message(const json& message, const std::vector<FaultTimeline*>& timelines) {
  FaultKeys keys;
  for (const auto& [key, value] : message.items()) {
    if (key == "receiver") continue;
    if (key == "at" || key == "at_utc" || key == "end")
      throw std::invalid_argument(fmt::format("{}: a live fault starts at the next epoch (give duration to end it)", key));
    const std::string name = key == "fault" ? "kind" : key;
    if (value.is_number()) {
      keys.emplace_back(name, value.get<double>());
    } else if (value.is_string()) {
      keys.emplace_back(name, value.get<std::string>());
    } else if (value.is_boolean()) {
      keys.emplace_back(name, std::string(value.get<bool>() ? "true" : "false"));
    } else {
      throw std::invalid_argument(fmt::format("{}: expected a number or a string, got {}", key, value.dump()));
    }
  }
  const Fault fault = make_fault(keys, FaultSource::live);
  const std::vector<std::size_t> receivers = receivers_of(message, timelines.size());
  for (const std::size_t i : receivers) {
    if (!fault.is<Spoof>()) break;
    if (const auto other = spoof_on(*timelines[i])) {
      throw std::invalid_argument(fmt::format("spoof: receiver {} has a spoof on ({}): two spoofers would add their drags; "
                                              "clear spoof first", i, *other));
    }
    if (const auto ahead = spoof_ahead(i, *timelines[i], fault)) throw std::invalid_argument(*ahead);
  }
  for (const std::size_t i : receivers) timelines[i]->add_live(fault, recorded(message, i));
  const std::string what = live_description(fault);
  spdlog::info("control: fault {} for receivers {}: from the next epoch", what, receivers_json(receivers).dump());
  json answer{{"class", "FAULT"}, {"fault", std::string(kind_name(fault.kind()))}, {"describe", what},
              {"receivers", receivers_json(receivers)}, {"starts", "next epoch"}};
  add_last_epoch(answer, *timelines[receivers.front()]);
  return answer.dump();
}

std::string clear_message(const json& message, const std::vector<FaultTimeline*>& timelines) {
  const json& what = message["clear"];
  if (!what.is_string()) throw std::invalid_argument(fmt::format("clear: expected a fault kind or \"all\", got {}", what.dump()));
  const std::string name = what.get<std::string>();
  std::vector<FaultKind> kinds;
  if (name == "all") {
    kinds.assign(kAllKinds.begin(), kAllKinds.end());
  } else if (const auto k = parse_kind(name)) {
    kinds.push_back(*k);
  } else {
    throw std::invalid_argument(fmt::format("clear: unknown fault '{}' (one of {}, or all)", name, kind_names()));
  }
  const std::vector<std::size_t> receivers = receivers_of(message, timelines.size());
  int cleared = 0;
  for (const std::size_t i : receivers) {
    // The request is recorded once a receiver (with its first kind), for the --tee file.
    for (std::size_t k = 0; k < kinds.size(); ++k) cleared += timelines[i]->clear(kinds[k], k == 0 ? recorded(message, i) : "");
  }
  spdlog::info("control: clear {} for receivers {}: {} faults end at the next epoch", name, receivers_json(receivers).dump(), cleared);
  json answer{{"class", "CLEAR"}, {"clear", name}, {"receivers", receivers_json(receivers)}, {"cleared", cleared}};
  add_last_epoch(answer, *timelines[receivers.front()]);
  return answer.dump();
}

std::string status_message(const std::vector<FaultTimeline*>& timelines,
                           const std::function<std::string(std::size_t)>& extra) {
  json receivers = json::array();
  for (std::size_t i = 0; i < timelines.size(); ++i) {
    const FaultTimeline& t = *timelines[i];
    const FaultTimeline::LastEpoch& last = t.last_epoch();
    json faults = json::array();
    for (const FaultTimeline::Entry& e : t.entries()) {
      if (e.ended) continue;
      json f{{"fault", std::string(kind_name(e.fault.kind()))}, {"describe", e.fault.describe()}, {"active", e.active},
             {"epochs", e.epochs}};
      if (!e.cleared && t.clear_pending(e.fault.kind())) f["ends"] = "next epoch";
      faults.push_back(std::move(f));
    }
    // Accepted since the last epoch: they start at the next one.
    for (const Fault& p : t.pending()) {
      faults.push_back({{"fault", std::string(kind_name(p.kind()))}, {"describe", live_description(p)}, {"active", false},
                        {"pending", true}, {"starts", "next epoch"}, {"epochs", 0}});
    }
    receivers.push_back({{"receiver", i}, {"epochs", last.epochs}, {"time_s", last.since_s},
                         {"quality", static_cast<int>(last.quality)}, {"satellites_used", last.satellites_used},
                         {"silent", last.silent}, {"faults", faults}});
    if (extra) {
      const json more = json::parse(extra(i), nullptr, false);
      if (more.is_object()) receivers.back().update(more);
    }
  }
  return json{{"class", "STATUS"}, {"receivers", receivers}}.dump();
}

}  // namespace

std::string control_error(std::string_view message) {
  return json{{"class", "ERROR"}, {"message", std::string(message)}}.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string FaultControl::handle(std::string_view line) {
  if (const std::optional<std::string> problem = json_shape_problem(line)) {
    ++refused_shape_;
    return control_error(fmt::format("refused before parsing: {}", *problem));
  }
  const json message = json::parse(line, nullptr, false);
  if (message.is_discarded() || !message.is_object()) return control_error("expected one JSON object a line, e.g. {\"status\":true}");
  try {
    if (message.contains("fault")) return fault_message(message, receivers_);
    if (message.contains("clear")) return clear_message(message, receivers_);
    if (message.contains("status")) return status_message(receivers_, status_extra_);
    return control_error("expected \"fault\", \"clear\" or \"status\", e.g. {\"fault\":\"jam\",\"db\":25,\"ramp_s\":5}");
  } catch (const std::exception& e) {
    return control_error(e.what());
  }
}

}  // namespace gpsemu::faults
