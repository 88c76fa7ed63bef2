#include "tools/cli_doc/completion.hpp"

#include <algorithm>
#include <regex>
#include <string>
#include <vector>

#include "tools/cli_doc/cli_walk.hpp"

namespace gpsemu::cli_doc {
namespace {

std::string joined(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

std::vector<std::string> flags_of(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::Option* o : options_of(app, false))
    for (const auto& n : flag_names(*o)) out.push_back(n);
  return out;
}

bool takes_a_file(const std::string& value) {
  return value.find("FILE") != std::string::npos || value == "LOG" || value == "PATH";
}

/// The fixed values a help text lists as "a | b | c" (lower-case words, none followed by ':' or
/// '[': "sim:line | sim:circle" and "pty[:LINK] | stdout" are specs, not values); empty if none.
std::vector<std::string> listed_values(const std::string& help) {
  static const std::regex run(R"((^|[\s(])([a-z0-9][a-z0-9.-]*(?: \| [a-z0-9][a-z0-9.-]*)+)(?![\w:\[]))");
  std::smatch m;
  if (!std::regex_search(help, m, run)) return {};
  std::vector<std::string> values;
  const std::string list = m[2];
  for (std::size_t start = 0;;) {
    const std::size_t bar = list.find(" | ", start);
    values.push_back(list.substr(start, bar == std::string::npos ? std::string::npos : bar - start));
    if (bar == std::string::npos) break;
    start = bar + 3;
  }
  return values;
}

/// `case $prev in` arms: what follows a flag that takes a value (each flag once). Values to type
/// (numbers, specs) complete to nothing: their flags are gathered in `free`, one arm at the end.
void value_cases(std::ostream& out, const std::vector<const CLI::Option*>& opts, std::vector<std::string>& done,
                 std::vector<std::string>& free) {
  for (const CLI::Option* o : opts) {
    const std::string value = value_name(*o);
    std::string arm;
    for (const auto& n : flag_names(*o)) arm += (arm.empty() ? "" : "|") + n;
    if (value.empty() || std::find(done.begin(), done.end(), arm) != done.end()) continue;
    done.push_back(arm);
    const auto values = listed_values(o->get_description());
    if (takes_a_file(value)) {
      out << "    " << arm << ") compopt -o filenames 2>/dev/null; mapfile -t COMPREPLY < <(compgen -f -- \"$cur\"); return ;;\n";
    } else if (!values.empty()) {
      out << "    " << arm << ") mapfile -t COMPREPLY < <(compgen -W \"" << joined(values) << "\" -- \"$cur\"); return ;;\n";
    } else {
      free.push_back(arm);
    }
  }
}

}  // namespace

void write_bash_completion(std::ostream& out, const CLI::App& app) {
  const auto subs = subcommands_of(app);
  std::vector<std::string> sub_names;
  std::vector<std::string> with_arguments;  // subcommands that take file arguments
  for (const CLI::App* s : subs) {
    sub_names.push_back(s->get_name());
    if (!options_of(*s, true).empty()) with_arguments.push_back(s->get_name());
  }
  std::vector<std::string> main_flags = flags_of(app);
  main_flags.insert(main_flags.begin(), {"--help", "--version"});
  std::string sub_pattern = joined(sub_names);
  std::replace(sub_pattern.begin(), sub_pattern.end(), ' ', '|');

  out << "# bash completion for gpsemu, generated from the command line gpsemu parses (tools/cli_doc):\n"
         "# do not edit.\n"
         "_gpsemu() {\n"
         "  local cur=${COMP_WORDS[COMP_CWORD]} prev=\"\" sub=\"\" w\n"
         "  ((COMP_CWORD > 0)) && prev=${COMP_WORDS[COMP_CWORD - 1]}\n"
         "  for w in \"${COMP_WORDS[@]:1:COMP_CWORD-1}\"; do\n"
         "    case $w in " << sub_pattern << ") sub=$w; break ;; esac\n"
         "  done\n"
         "  case $prev in\n";
  std::vector<std::string> done;
  std::vector<std::string> free;
  value_cases(out, options_of(app, false), done, free);
  for (const CLI::App* s : subs) value_cases(out, options_of(*s, false), done, free);
  std::string free_arm = joined(free);
  std::replace(free_arm.begin(), free_arm.end(), ' ', '|');
  if (!free_arm.empty()) out << "    " << free_arm << ") return ;;\n";
  out << "  esac\n"
         "  local flags=\"" << joined(main_flags) << "\"\n"
         "  case $sub in\n";
  for (const CLI::App* s : subs) {
    const auto own = flags_of(*s);
    if (!own.empty()) out << "    " << s->get_name() << ") flags+=\" " << joined(own) << "\" ;;\n";
  }
  out << "  esac\n"
         "  if [[ $cur == -* ]]; then\n"
         "    mapfile -t COMPREPLY < <(compgen -W \"$flags\" -- \"$cur\")\n"
         "  elif [[ -z $sub ]]; then\n"
         "    mapfile -t COMPREPLY < <(compgen -W \"" << joined(sub_names) << "\" -- \"$cur\")\n";
  if (!with_arguments.empty()) {
    std::string pattern = joined(with_arguments);
    std::replace(pattern.begin(), pattern.end(), ' ', '|');
    out << "  elif [[ $sub == @(" << pattern << ") ]]; then\n"
           "    compopt -o filenames 2>/dev/null\n"
           "    mapfile -t COMPREPLY < <(compgen -f -- \"$cur\")\n";
  }
  out << "  fi\n"
         "}\n"
         "complete -F _gpsemu gpsemu\n";
}

}  // namespace gpsemu::cli_doc
