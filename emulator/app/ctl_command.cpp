// gpsemu ctl PATH ...: the control socket's command-line client (docs/faults.md). PATH is a Unix
// socket's path (or unix:PATH), or tcp:HOST:PORT for --control tcp:...
//   gpsemu ctl PATH jam --db 25 --ramp 5 [--receiver 0] [--duration 10]   a fault from the next epoch
//     (every parameter of every kind has a flag: faults/control_args.hpp)
//   gpsemu ctl PATH clear jam [--receiver 0]                                end it
//   gpsemu ctl PATH status                                                  the receivers and their faults
//   gpsemu ctl PATH send '{"status":true}'                                  one raw JSON line
//   gpsemu ctl PATH watch [--receiver N] [--count N]   one JSON line an epoch (docs/ui.md), as the bench view shows it
// Prints the answer; exit 0, 1 for an ERROR answer, 2 for a bad command line or no socket.
#include <charconv>
#include <cstdio>
#include <optional>
#include <utility>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/app/subcommands.hpp"
#include "emulator/faults/control_args.hpp"
#include "emulator/pipeline/control_socket.hpp"

namespace gpsemu {
namespace {

/// `ctl PATH watch [--receiver N] [--count N]`: prints each EPOCH line (N of them, or until gpsemu
/// stops); the WATCH acknowledgement is not printed. Exit 0, 1 for an ERROR answer.
int watch(const std::string& path, const std::vector<std::string>& words) {
  nlohmann::json request{{"watch", true}};
  std::optional<std::uint64_t> count;
  for (std::size_t k = 0; k < words.size(); k += 2) {
    const std::string& flag = words[k];
    if ((flag != "--receiver" && flag != "--count") || k + 1 >= words.size()) {
      throw std::invalid_argument(fmt::format("ctl watch: unexpected '{}' (flags: --receiver N, --count N)", flag));
    }
    std::uint64_t value = 0;
    const std::string& text = words[k + 1];
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) {
      throw std::invalid_argument(fmt::format("ctl watch: {} expects a whole number, got '{}'", flag, text));
    }
    if (flag == "--receiver") request["receiver"] = value;
    if (flag == "--count") count = value;
  }
  int status = 0;
  std::uint64_t printed = 0;
  bool first = true;
  control_watch(path, request.dump(), std::chrono::seconds(30), [&](std::string_view line) {
    if (std::exchange(first, false)) {
      if (nlohmann::json::parse(line, nullptr, false).value("class", "") == "WATCH") return !count || *count > 0;
      std::fputs((std::string(line) + "\n").c_str(), stdout);
      status = 1;
      return false;
    }
    std::fputs((std::string(line) + "\n").c_str(), stdout);
    std::fflush(stdout);
    return !count || ++printed < *count;
  });
  return status;
}

}  // namespace

Subcommand add_ctl_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "ctl", "control a running gpsemu (--control unix:PATH or tcp:HOST:PORT): `ctl PATH KIND --FLAG VALUE...` starts "
             "a fault at the next epoch (a jam of 25 dB ramped over 5 s: ctl PATH jam --db 25 --ramp 5), "
             "`ctl PATH clear KIND`, `ctl PATH status`, `ctl PATH send JSON`, `ctl PATH watch [--receiver N] [--count N]` "
             "(one JSON line an epoch, the bench view's data); prints the JSON answer; exit 0, 1 for an "
             "ERROR answer, 2 when it cannot connect or the command line is wrong (docs/faults.md)");
  sub->footer(faults::control_flags_help());
  // Shown in the help and the CLI reference; the words are read from remaining() (the flags depend on KIND).
  sub->add_option("PATH", "the control socket: PATH (or unix:PATH) of --control unix:PATH, or tcp:HOST:PORT");
  sub->add_option("COMMAND", "KIND (outage, jam, spoof, ...) with its flags (gpsemu ctl --help lists them), clear KIND, status, "
                             "send JSON, or watch");
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
            if (args.size() >= 2 && args[1] == "watch") return watch(args[0], std::vector<std::string>(args.begin() + 2, args.end()));
            const std::string request = faults::control_request_of(std::vector<std::string>(args.begin() + 1, args.end()));
            const std::string answer = control_request(args[0], request, std::chrono::seconds(5));
            std::fputs((answer + "\n").c_str(), stdout);
            return nlohmann::json::parse(answer, nullptr, false).value("class", "") == "ERROR" ? 1 : 0;
          }};
}

}  // namespace gpsemu
