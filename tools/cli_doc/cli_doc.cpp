// gpsemu-cli-doc: writes docs/cli.md, the command-line reference, from the very CLI11 application
// main() parses (gpsemu::make_command_line()). It walks the main app (every option: name, value
// name, help, whether it repeats) and every subcommand (its positionals and options), so the
// reference cannot drift from `gpsemu --help`. tools/update-cli-doc runs it; the CTest
// docs.cli_reference_is_current fails when the checked-in docs/cli.md differs from its output.
//
//   gpsemu-cli-doc            markdown on stdout
//   gpsemu-cli-doc FILE       markdown into FILE
#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "emulator/app/command_line.hpp"

namespace {

/// Markdown table cells: a `|` ends the cell unless escaped; newlines end the row.
std::string cell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

/// A description as a sentence: capital first letter, full stop at the end.
std::string sentence(std::string text) {
  if (!text.empty() && text.front() >= 'a' && text.front() <= 'z')
    text.front() = static_cast<char>(text.front() - 'a' + 'A');
  if (!text.empty() && text.back() != '.') text += '.';
  return text;
}

std::string code(const std::string& text) { return text.empty() ? std::string() : "`" + cell(text) + "`"; }

/// The flag names of an option, long names first: `--config-out`, `-o`.
std::string names(const CLI::Option& opt) {
  std::vector<std::string> all;
  for (const auto& l : opt.get_lnames()) all.push_back("`--" + l + "`");
  for (const auto& s : opt.get_snames()) all.push_back("`-" + s + "`");
  std::string out;
  for (const auto& n : all) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// What the user writes after the flag ("HZ", "SPEC"); empty for a flag without a value.
std::string value_name(const CLI::Option& opt) {
  if (opt.get_type_size_max() == 0) return {};
  if (!opt.get_option_text().empty()) return opt.get_option_text();
  return opt.get_type_name();
}

bool repeatable(const CLI::Option& opt) { return opt.get_type_size_max() > 0 && opt.get_expected_max() > 1; }

/// Where an option applies, from the option table's scope (process, fleet, timeline, pps,
/// receiver: may differ per [[receiver]] table, replay: `gpsemu replay` only). Empty for the
/// options that are not in the table (--config, the subcommands' own): the column shows nothing.
std::string scope_of(const CLI::Option& opt) {
  if (opt.get_lnames().empty()) return {};
  const gpsemu::OptionDef* def = gpsemu::find_option(opt.get_lnames().front());
  if (def == nullptr) return {};
  switch (def->scope) {
    case gpsemu::OptionScope::process: return "process";
    case gpsemu::OptionScope::fleet: return "fleet";
    case gpsemu::OptionScope::timeline: return "timeline";
    case gpsemu::OptionScope::pps: return "pps";
    case gpsemu::OptionScope::receiver: return "receiver";
    case gpsemu::OptionScope::replay: return "replay";
  }
  return {};
}

bool is_help_or_version(const CLI::Option& opt) {
  return opt.check_lname("help") || opt.check_lname("help-all") || opt.check_lname("version");
}

void options_table(std::ostream& out, const std::vector<const CLI::Option*>& opts) {
  const bool with_scope = std::any_of(opts.begin(), opts.end(),
                                      [](const CLI::Option* o) { return !scope_of(*o).empty(); });
  out << "| option | value | repeatable |" << (with_scope ? " scope |" : "") << " description |\n";
  out << "|---|---|---|" << (with_scope ? "---|" : "") << "---|\n";
  for (const CLI::Option* o : opts) {
    out << "| " << names(*o) << " | " << code(value_name(*o)) << " | " << (repeatable(*o) ? "yes" : "")
        << " |";
    if (with_scope) out << ' ' << scope_of(*o) << " |";
    out << ' ' << cell(o->get_description()) << " |\n";
  }
}

void positionals_list(std::ostream& out, const std::vector<const CLI::Option*>& positionals) {
  out << "Arguments:\n\n";
  for (const CLI::Option* p : positionals) {
    const std::string shown = p->get_option_text().empty() ? p->get_name() : p->get_option_text();
    out << "- `" << shown << "`" << (p->get_required() ? "" : " (optional)") << ": " << p->get_description()
        << "\n";
  }
  out << "\n";
}

std::vector<const CLI::Option*> named(const CLI::App& app, bool positional) {
  return app.get_options([positional](const CLI::Option* o) {
    return o->nonpositional() != positional && (positional || !is_help_or_version(*o));
  });
}

std::string usage(const CLI::App& sub) {
  std::string line = "gpsemu " + sub.get_name();
  for (const CLI::Option* p : named(sub, true))
    line += " " + (p->get_option_text().empty() ? p->get_name() : p->get_option_text());
  if (!named(sub, false).empty()) line += " [OPTIONS]";
  return line;
}

void write_reference(std::ostream& out, const CLI::App& app) {
  auto subs = app.get_subcommands([](const CLI::App*) { return true; });
  std::sort(subs.begin(), subs.end(),
            [](const CLI::App* a, const CLI::App* b) { return a->get_name() < b->get_name(); });

  out << "<!-- Generated by tools/update-cli-doc (gpsemu-cli-doc walks the CLI11 application that\n"
         "     gpsemu's main() parses). Do not edit by hand: the test docs.cli_reference_is_current fails. -->\n"
         "# gpsemu command-line reference\n\n"
      << sentence(app.get_description()) << "\n\n"
      << "```\ngpsemu [OPTIONS]\ngpsemu SUBCOMMAND ARGUMENTS [OPTIONS]\n```\n\n"
      << "Every option of the emulator except `--config` is also a key of the TOML config file given with\n"
         "`--config FILE` (the key is the long flag name without dashes; a repeatable option is an array).\n"
         "Flags override the file. `--help` prints this list; `--version` the version. A bad flag, value\n"
         "or key prints one message naming it and exits with status 2.\n\n"
      << "Subcommands:";
  for (const CLI::App* s : subs) out << " [`" << s->get_name() << "`](#gpsemu-" << s->get_name() << ")";
  out << ".\n\n## gpsemu\n\n";
  options_table(out, named(app, false));

  for (const CLI::App* s : subs) {
    out << "\n## gpsemu " << s->get_name() << "\n\n" << sentence(s->get_description()) << "\n\n";
    out << "```\n" << usage(*s) << "\n```\n\n";
    const auto positionals = named(*s, true);
    if (!positionals.empty()) positionals_list(out, positionals);
    const auto opts = named(*s, false);
    if (!opts.empty()) {
      out << "Options of `" << s->get_name() << "` (the options of `gpsemu` are accepted too, before or after"
          << " the subcommand's name):\n\n";
      options_table(out, opts);
    } else {
      out << "No options of its own; the options of `gpsemu` are accepted too.\n";
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2) {
    std::cerr << "usage: gpsemu-cli-doc [FILE]  (markdown CLI reference; stdout without FILE)\n";
    return 2;
  }
  const auto command_line = gpsemu::make_command_line();
  std::ostringstream text;
  write_reference(text, command_line->app);
  if (argc == 1) {
    std::cout << text.str();
    return 0;
  }
  std::ofstream file(argv[1], std::ios::binary);
  file << text.str();
  if (!file.flush()) {
    std::cerr << "gpsemu-cli-doc: cannot write " << argv[1] << "\n";
    return 1;
  }
  return 0;
}
