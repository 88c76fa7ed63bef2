// Walking the CLI11 application gpsemu's main() parses (gpsemu::make_command_line()): its options
// without --help/--version, what each takes, and the subcommands in name order. The generated
// documents (docs/cli.md, the man page, the bash completion) read the command line through these.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace gpsemu::cli_doc {

inline bool is_help_or_version(const CLI::Option& opt) {
  return opt.check_lname("help") || opt.check_lname("help-all") || opt.check_lname("version");
}

/// The options of `app` with a flag name (positional = false) or its positional arguments (true).
inline std::vector<const CLI::Option*> options_of(const CLI::App& app, bool positional) {
  return app.get_options([positional](const CLI::Option* o) {
    return o->nonpositional() != positional && (positional || !is_help_or_version(*o));
  });
}

/// The flag names of an option, long names first ("--config-out", "-o") or short ones first.
inline std::vector<std::string> flag_names(const CLI::Option& opt, bool short_first = false) {
  std::vector<std::string> longs;
  std::vector<std::string> shorts;
  for (const auto& l : opt.get_lnames()) longs.push_back("--" + l);
  for (const auto& s : opt.get_snames()) shorts.push_back("-" + s);
  auto& all = short_first ? shorts : longs;
  const auto& rest = short_first ? longs : shorts;
  all.insert(all.end(), rest.begin(), rest.end());
  return all;
}

/// What the user writes after the flag ("HZ", "SPEC"); empty for a flag without a value.
inline std::string value_name(const CLI::Option& opt) {
  if (opt.get_type_size_max() == 0) return {};
  if (!opt.get_option_text().empty()) return opt.get_option_text();
  return opt.get_type_name();
}

/// A positional argument as shown in a synopsis ("LOG").
inline std::string positional_name(const CLI::Option& opt) {
  return opt.get_option_text().empty() ? opt.get_name() : opt.get_option_text();
}

inline bool repeatable(const CLI::Option& opt) {
  return opt.get_type_size_max() > 0 && opt.get_expected_max() > 1;
}

/// A help text ended with a full stop (as `--help` shows it otherwise).
inline std::string ended(std::string text) {
  if (!text.empty() && text.back() != '.') text += '.';
  return text;
}

/// A description as a sentence: capital first letter, full stop at the end.
inline std::string sentence(std::string text) {
  if (!text.empty() && text.front() >= 'a' && text.front() <= 'z')
    text.front() = static_cast<char>(text.front() - 'a' + 'A');
  return ended(text);
}

/// The subcommands in name order.
inline std::vector<const CLI::App*> subcommands_of(const CLI::App& app) {
  auto subs = app.get_subcommands([](const CLI::App*) { return true; });
  std::vector<const CLI::App*> out(subs.begin(), subs.end());
  std::sort(out.begin(), out.end(), [](const CLI::App* a, const CLI::App* b) { return a->get_name() < b->get_name(); });
  return out;
}

}  // namespace gpsemu::cli_doc
