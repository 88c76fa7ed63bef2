// gpsemu: a GPS receiver emulator. Parses the command line and config file, sets up logging and
// signals, and runs the main loop. Exit status: 0 done, 1 every output gone (the reader of the pipe
// left), 2 bad configuration or start-up failure, 3 no output took any epoch (every write failed).
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "emulator/app/command_line.hpp"
#include "emulator/app/subcommands.hpp"
#include "emulator/config/config.hpp"
#include "emulator/config/config_values.hpp"
#include "emulator/config/profiles.hpp"
#include "emulator/config/validate.hpp"
#include "emulator/pipeline/runner.hpp"
#include "emulator/ui/http_server.hpp"
#include "transport/posix/realtime.hpp"

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop.store(true); }

void install_signal_handlers() {
  struct sigaction sa{};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a signal interrupts sleeps so shutdown is prompt
  // HUP (the terminal went away) and QUIT shut down like TERM: pty link removed, summary logged,
  // exit 0. (No log-rotation reopen: file outputs are for batch runs; docs/reliability.md.)
  for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaction(sig, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

void setup_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("gpsemu");
  logger->set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(level));
}

/// A start-up error: one line "gpsemu: WHAT" on stderr (exit status 2 follows), whatever raised it.
void fail(const std::string& message) {
  std::string what = gpsemu::config_values::shorten_quoted(message);
  std::replace(what.begin(), what.end(), '\n', ' ');
  std::fprintf(stderr, "gpsemu: %s\n", what.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  const auto cl = gpsemu::make_command_line();
  CLI::App& app = cl->app;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fail(std::string(e.what()) + " (gpsemu --help lists the options)");
    return 2;
  }
  const gpsemu::RawOptions command_line = cl->given();
  const std::string& config_file = cl->config_file;
  const auto& subcommands = cl->subcommands;

  gpsemu::Config config;
  try {
    // Templates, shared outputs and specs are checked here, before anything opens.
    config = gpsemu::build_config(config_file.empty() ? std::nullopt : std::optional{config_file}, command_line);
  } catch (const std::exception& e) {
    fail(e.what());
    return 2;
  }
  setup_logging(config.process.log_level);
  install_signal_handlers();

  for (const auto& sc : subcommands) {
    if (!sc.app->parsed()) continue;
    try {
      gpsemu::check_subcommand(config, sc.app->get_name());
    } catch (const std::exception& e) {
      fail(e.what());
      return 2;
    }
    try {
      return sc.run(config, g_stop);
    } catch (const std::exception& e) {
      fail(e.what());
      return 2;
    }
  }

  // Replay's options mean nothing to the emulator loop: say so instead of ignoring them.
  for (const auto& [name, values] : command_line) {
    if (gpsemu::is_replay_only(name)) {
      fail("--" + name + " applies to 'gpsemu replay LOG' only");
      return 2;
    }
  }

  std::unique_ptr<gpsemu::Runner> runner;
  std::unique_ptr<gpsemu::ui::HttpServer> bench_view;  // after the runner: stopped before its hub goes
  try {
    gpsemu::check_emulator_run(config);
    if (config.process.profile) {
      const auto s = gpsemu::profiles::summary(gpsemu::profiles::get(*config.process.profile));
      spdlog::info("profile {}: {}, calibrated from {} (the config file's keys and the flags override it)", s.name,
                   s.receiver, s.log);
    }
    // The bench view's port first: one in use stops the start before an output is opened (a file truncated).
    std::unique_ptr<gpsemu::ui::HttpServer> bound_view;
    if (config.process.ui) {
      gpsemu::ui::HttpSettings ui = gpsemu::ui::parse_ui_spec(*config.process.ui);
      ui.token = config.process.ui_token;
      bound_view = std::make_unique<gpsemu::ui::HttpServer>(ui);
    }
    runner = std::make_unique<gpsemu::Runner>(config);
    if (bound_view) {
      bench_view = std::move(bound_view);
      bench_view->serve(*runner->hub());
      spdlog::info("bench view: {}{}", bench_view->url(),
                   bench_view->token_required() ? " (fault requests need this token: header X-Gpsemu-Token)" : "");
    }
  } catch (const std::exception& e) {
    fail(e.what());
    return 2;
  }
  for (const std::string& line : gpsemu::posix::apply_realtime_settings(config.process.realtime)) spdlog::info("{}", line);
  const int status = runner->run(g_stop);
  if (bench_view) {
    spdlog::info("{}", bench_view->summary());
    bench_view.reset();
  }
  return status;
}
