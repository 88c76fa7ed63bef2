#include "emulator/faults/tee_events.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace gpsemu::faults {
namespace {

using nlohmann::json;

constexpr std::string_view kPrefix = "# fault +";

/// A recorded request's keys for make_fault (the control socket's "fault" is the table's "kind").
FaultKeys keys_of(const json& request) {
  FaultKeys keys;
  for (const auto& [key, value] : request.items()) {
    const std::string name = key == "fault" ? "kind" : key;
    if (value.is_number()) {
      keys.emplace_back(name, value.get<double>());
    } else if (value.is_string()) {
      keys.emplace_back(name, value.get<std::string>());
    } else {
      throw std::invalid_argument(fmt::format("{}: expected a number or a string, got {}", key, value.dump()));
    }
  }
  return keys;
}

/// Ends, at `since_s`, the faults of `kind` (none: every kind) for `receiver` (none: all) still on.
void clear_faults(std::vector<Fault>& faults, std::optional<FaultKind> kind, std::optional<int> receiver, double since_s) {
  const auto ns = [](double s) { return std::llround(s * 1e9); };
  for (auto it = faults.begin(); it != faults.end();) {
    const bool matches = (!kind || it->kind() == *kind) && (!receiver || !it->receiver || *it->receiver == *receiver);
    if (matches && it->where) {
      // An area's fault: disarmed from the clear on (its visits before stay as they were).
      if (!it->disarm_s || ns(*it->disarm_s) > ns(since_s)) it->disarm_s = since_s;
      ++it;
      continue;
    }
    const bool on = !it->duration_s || ns(it->at_s + *it->duration_s) > ns(since_s);
    if (matches && on) {
      if (ns(since_s) <= ns(it->at_s)) {
        it = faults.erase(it);  // cleared before it began
        continue;
      }
      it->duration_s = since_s - it->at_s;
    }
    ++it;
  }
}

}  // namespace

std::string tee_event_line(const AppliedEvent& event) {
  return fmt::format("{}{:.9f} {} {}", kPrefix, event.since_s, format_iso8601_utc(event.epoch), event.request);
}

bool looks_like_tee(std::string_view text) {
  for (std::size_t at = 0; at < text.size();) {
    const std::string_view line = text.substr(at, text.find('\n', at) - at);
    if (line.rfind("# sent ", 0) == 0 || line.rfind(kPrefix, 0) == 0) return true;
    const std::size_t nl = text.find('\n', at);
    if (nl == std::string_view::npos) break;
    at = nl + 1;
  }
  return false;
}

std::vector<Fault> faults_from_tee(std::string_view text) {
  std::vector<Fault> out;
  int number = 0;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t nl = text.find('\n', at);
    std::string_view line = text.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
    at = nl == std::string_view::npos ? text.size() : nl + 1;
    ++number;
    if (line.rfind(kPrefix, 0) != 0) continue;
    try {
      line.remove_prefix(kPrefix.size());
      const std::size_t space = line.find(' ');
      double since_s = 0.0;
      const auto [end, ec] = std::from_chars(line.data(), line.data() + std::min(space, line.size()), since_s);
      if (ec != std::errc() || space == std::string_view::npos)
        throw std::invalid_argument("expected '# fault +SECONDS EPOCH_TIME {JSON}'");
      const std::size_t brace = line.find('{', space);
      if (brace == std::string_view::npos) throw std::invalid_argument("no JSON request");
      const json request = json::parse(line.substr(brace), nullptr, false);
      if (request.is_discarded() || !request.is_object()) throw std::invalid_argument("the request is not one JSON object");
      std::optional<int> receiver;
      if (const auto r = request.find("receiver"); r != request.end() && r->is_number_integer()) receiver = r->get<int>();
      if (request.contains("clear")) {
        const std::string name = request["clear"].is_string() ? request["clear"].get<std::string>() : "";
        const std::optional<FaultKind> kind = parse_kind(name);
        if (!kind && name != "all") throw std::invalid_argument(fmt::format("clear: unknown fault '{}'", name));
        clear_faults(out, kind, receiver, since_s);
      } else if (request.contains("fault")) {
        Fault f = make_fault(keys_of(request));
        f.at_s = since_s;
        out.push_back(std::move(f));
      } else {
        throw std::invalid_argument("expected a \"fault\" or a \"clear\" request");
      }
    } catch (const std::exception& e) {
      throw std::invalid_argument(fmt::format("line {}: {}", number, e.what()));
    }
  }
  return out;
}

}  // namespace gpsemu::faults
