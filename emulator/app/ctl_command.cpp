// gpsemu ctl PATH ...: the control socket's command-line client (docs/faults.md). PATH is a Unix
// socket's path (or unix:PATH), or tcp:HOST:PORT for --control tcp:...
//   gpsemu ctl PATH jam --db 25 --ramp 5 [--receiver 0] [--duration 10]   a fault from the next epoch
//   gpsemu ctl PATH clear jam [--receiver 0]                                end it
//   gpsemu ctl PATH status                                                  the receivers and their faults
//   gpsemu ctl PATH send '{"status":true}'                                  one raw JSON line
// Prints the answer; exit 0, 1 for an ERROR answer, 2 for a bad command line or no socket.
#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/app/subcommands.hpp"
#include "emulator/config/config_values.hpp"
#include "emulator/pipeline/control_socket.hpp"

namespace gpsemu {
namespace {

/// A flag's key: dashes to underscores, and the short names of the issue (--ramp) with their units.
std::string key_of(std::string flag) {
  for (char& c : flag) {
    if (c == '-') c = '_';
  }
  for (const char* unit_less : {"ramp", "decay"}) {
    if (flag == unit_less) return flag + "_s";
  }
  for (const char* unit_less : {"east", "north", "up"}) {
    if (flag == unit_less) return flag + "_m";
  }
  return flag;
}

/// "25" as a number, anything else as a string.
nlohmann::json value_of(const std::string& text) {
  try {
    std::size_t used = 0;
    const double x = std::stod(text, &used);
    if (used == text.size()) return x;
  } catch (const std::exception&) {
  }
  return text;
}

/// The JSON line of `args` (after PATH). Throws std::invalid_argument.
std::string request_of(const std::vector<std::string>& args) {
  if (args.empty()) throw std::invalid_argument("ctl: expected PATH and a command: KIND [--PARAM VALUE]..., clear KIND, status or send JSON");
  const std::string& command = args[0];
  if (command == "status") return R"({"status":true})";
  if (command == "send") {
    if (args.size() != 2) throw std::invalid_argument("ctl send: expected one JSON line");
    return args[1];
  }
  nlohmann::json message;
  std::size_t i = 1;
  if (command == "clear") {
    if (args.size() < 2) throw std::invalid_argument("ctl clear: expected a fault kind or all");
    message["clear"] = args[1];
    i = 2;
  } else {
    message["fault"] = command;
  }
  for (; i < args.size(); i += 2) {
    if (args[i].rfind("--", 0) != 0 || i + 1 >= args.size())
      throw std::invalid_argument(fmt::format("ctl: expected --PARAM VALUE, got '{}'", args[i]));
    message[key_of(args[i].substr(2))] = value_of(args[i + 1]);
  }
  return message.dump();
}

}  // namespace

Subcommand add_ctl_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "ctl", "control a running gpsemu (--control unix:PATH or tcp:HOST:PORT; PATH may be tcp:HOST:PORT): `ctl PATH KIND` with the fault's parameters as flags "
             "(a jam of 25 dB ramped over 5 s: db 25, ramp 5), `ctl PATH clear KIND`, `ctl PATH status`, "
             "`ctl PATH send JSON`; prints the JSON answer (docs/faults.md)");
  sub->prefix_command();
  return {sub, [sub](const Config&, const std::atomic<bool>&) {
            const std::vector<std::string> args = sub->remaining();
            if (args.empty()) throw std::invalid_argument("ctl: expected PATH and a command (status, clear KIND, KIND --PARAM VALUE ...)");
            const std::string request = request_of(std::vector<std::string>(args.begin() + 1, args.end()));
            const std::string answer = control_request(args[0], request, std::chrono::seconds(5));
            std::fputs((answer + "\n").c_str(), stdout);
            return nlohmann::json::parse(answer, nullptr, false).value("class", "") == "ERROR" ? 1 : 0;
          }};
}

}  // namespace gpsemu
