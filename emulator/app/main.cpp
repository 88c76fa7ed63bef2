// gpsemu: a GPS receiver emulator. Parses the command line and config file, sets up logging and
// signals, and runs the main loop. Exit status: 0 done, 2 bad configuration or start-up failure.
#include <csignal>
#include <cstdio>
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "emulator/config/config.hpp"
#include "emulator/config/fleet_config.hpp"
#include "emulator/pipeline/runner.hpp"
#include "emulator/app/subcommands.hpp"

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop.store(true); }

void install_signal_handlers() {
  struct sigaction sa{};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a signal interrupts sleeps so shutdown is prompt
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

void setup_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("gpsemu");
  logger->set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(level));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gpsemu: hardware-in-the-loop GPS receiver emulator (NMEA over a pty, file or stdout)",
               "gpsemu"};
  app.set_version_flag("--version", std::string("gpsemu ") + GPSEMU_VERSION);
  app.get_formatter()->column_width(34);
  std::string config_file;
  app.add_option("--config", config_file, "TOML config file; keys are the long flag names, flags override it")
      ->check(CLI::ExistingFile)
      ->option_text("FILE");

  std::map<std::string, std::vector<std::string>> values;
  std::map<std::string, CLI::Option*> options;
  for (const auto& def : gpsemu::option_table()) {
    auto& store = values[def.name];
    CLI::Option* opt = nullptr;
    if (def.value_name.empty()) {
      opt = app.add_flag("--" + def.name, def.help);
    } else {
      opt = app.add_option("--" + def.name, store, def.help)->type_name(def.value_name);
      // One value per occurrence: a value option never swallows a subcommand's positional
      // argument (`gpsemu replay --speed 10 LOG`).
      opt->allow_extra_args(false);
      if (!def.repeatable) opt->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    }
    options[def.name] = opt;
  }

  const std::vector<gpsemu::Subcommand> subcommands = gpsemu::add_subcommands(app);
  for (const auto& sc : subcommands) sc.app->fallthrough();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "gpsemu: %s\nRun 'gpsemu --help' for the options.\n", e.what());
    return 2;
  }

  gpsemu::RawOptions command_line;
  for (const auto& def : gpsemu::option_table()) {
    const CLI::Option* opt = options[def.name];
    if (opt->count() == 0) continue;
    command_line.emplace_back(def.name, def.value_name.empty() ? std::vector<std::string>{"true"}
                                                               : values[def.name]);
  }

  gpsemu::Config config;
  try {
    config = gpsemu::build_config(config_file.empty() ? std::nullopt : std::optional{config_file}, command_line);
    (void)gpsemu::receiver_configs(config);  // templates and shared outputs are checked before anything opens
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gpsemu: %s\n", e.what());
    return 2;
  }
  setup_logging(config.log_level);
  install_signal_handlers();

  for (const auto& sc : subcommands) {
    if (!sc.app->parsed()) continue;
    if (gpsemu::receiver_count(config) > 1) {
      std::fprintf(stderr, "gpsemu: --receivers and [[receiver]] tables apply to the emulator loop, not to 'gpsemu %s'\n",
                   sc.app->get_name().c_str());
      return 2;
    }
    try {
      return sc.run(config, g_stop);
    } catch (const std::exception& e) {
      spdlog::error("{}", e.what());
      return 2;
    }
  }

  // Replay's options mean nothing to the emulator loop: say so instead of ignoring them.
  for (const auto& [name, values] : command_line) {
    if (name == "speed" || name == "loop" || name == "from" || name == "to" || name == "retime") {
      std::fprintf(stderr, "gpsemu: --%s applies to 'gpsemu replay LOG' only\n", name.c_str());
      return 2;
    }
  }

  std::unique_ptr<gpsemu::Runner> runner;
  try {
    runner = std::make_unique<gpsemu::Runner>(config);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  for (const std::string& line : gpsemu::apply_realtime_settings(config.realtime)) spdlog::info("{}", line);
  return runner->run(g_stop);
}
