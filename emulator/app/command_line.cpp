#include "emulator/app/command_line.hpp"

namespace gpsemu {

std::unique_ptr<CommandLine> make_command_line() {
  auto cl = std::make_unique<CommandLine>();
  CLI::App& app = cl->app;
  app.set_version_flag("--version", std::string("gpsemu ") + GPSEMU_VERSION);
  app.get_formatter()->column_width(34);
  // Not CLI::ExistingFile: build_config() reads it, refusing FIFOs and devices with one message.
  app.add_option("--config", cl->config_file, "TOML config file (a regular file); keys are the long flag names, flags "
                 "override it, e.g. rate = 10 and output = [\"pty:/tmp/gps\", \"file:run.nmea\"]")
      ->option_text("FILE");
  for (const auto& def : option_table()) {
    auto& store = cl->values[def.name];
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
    cl->options[def.name] = opt;
  }
  cl->subcommands = add_subcommands(app);
  // A prefix command (ctl) takes every argument after it as its own.
  for (const auto& sc : cl->subcommands) sc.app->fallthrough(!sc.app->get_prefix_command());
  return cl;
}

RawOptions CommandLine::given() const {
  RawOptions command_line;
  for (const auto& def : option_table()) {
    const CLI::Option* opt = options.at(def.name);
    if (opt->count() == 0) continue;
    command_line.emplace_back(def.name, def.value_name.empty() ? std::vector<std::string>{"true"}
                                                               : values.at(def.name));
  }
  return command_line;
}

}  // namespace gpsemu
