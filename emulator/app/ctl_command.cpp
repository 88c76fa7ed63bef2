// gpsemu ctl PATH ...: the control socket's command-line client (docs/faults.md). PATH is a Unix
// socket's path (or unix:PATH), or tcp:HOST:PORT for --control tcp:...
//   gpsemu ctl PATH jam --db 25 --ramp 5 [--receiver 0] [--duration 10]   a fault from the next epoch
//     (every parameter of every kind has a flag: faults/control_args.hpp)
//   gpsemu ctl PATH clear jam [--receiver 0]                                end it
//   gpsemu ctl PATH status                                                  the receivers and their faults
//   gpsemu ctl PATH send '{"status":true}'                                  one raw JSON line
// Prints the answer; exit 0, 1 for an ERROR answer, 2 for a bad command line or no socket.
#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/app/subcommands.hpp"
#include "emulator/faults/control_args.hpp"
#include "emulator/pipeline/control_socket.hpp"

namespace gpsemu {

Subcommand add_ctl_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "ctl", "control a running gpsemu (--control unix:PATH or tcp:HOST:PORT): `ctl PATH KIND --FLAG VALUE...` starts "
             "a fault at the next epoch (a jam of 25 dB ramped over 5 s: ctl PATH jam --db 25 --ramp 5), "
             "`ctl PATH clear KIND`, `ctl PATH status`, `ctl PATH send JSON`; prints the JSON answer; exit 0, 1 for an "
             "ERROR answer, 2 when it cannot connect or the command line is wrong (docs/faults.md)");
  sub->footer(faults::control_flags_help());
  // Shown in the help and the CLI reference; the words are read from remaining() (the flags depend on KIND).
  sub->add_option("PATH", "the control socket: PATH (or unix:PATH) of --control unix:PATH, or tcp:HOST:PORT");
  sub->add_option("COMMAND", "KIND (outage, jam, spoof, ...) with its flags (gpsemu ctl --help lists them), clear KIND, status, or send JSON");
  sub->prefix_command();
  return {sub, [sub](const Config&, const std::atomic<bool>&) {
            std::vector<std::string> args;
            for (const CLI::Option* o : sub->get_options()) {
              if (o->get_positional()) {
                for (const std::string& r : o->results()) args.push_back(r);
              }
            }
            for (const std::string& r : sub->remaining()) args.push_back(r);
            if (args.empty()) throw std::invalid_argument("ctl: expected PATH and a command (status, clear KIND, KIND --FLAG VALUE ...)");
            const std::string request = faults::control_request_of(std::vector<std::string>(args.begin() + 1, args.end()));
            const std::string answer = control_request(args[0], request, std::chrono::seconds(5));
            std::fputs((answer + "\n").c_str(), stdout);
            return nlohmann::json::parse(answer, nullptr, false).value("class", "") == "ERROR" ? 1 : 0;
          }};
}

}  // namespace gpsemu
