#include "tools/cli_doc/man_page.hpp"

#include "tools/cli_doc/cli_walk.hpp"

namespace gpsemu::cli_doc {
namespace {

/// Text for roff: backslashes escaped, "-" as the minus sign \- (option names, ranges), a
/// control character at the start of a line neutralised, newlines as spaces.
std::string roff(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\\') out += "\\e";
    else if (c == '-') out += "\\-";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  if (!out.empty() && (out.front() == '.' || out.front() == '\'')) out.insert(0, "\\&");
  return out;
}

/// One option as a tagged paragraph: ".TP", "\fB\-\-output\fR \fISPEC\fR ...", its help.
void option_entry(std::ostream& out, const CLI::Option& opt) {
  out << ".TP\n";
  std::string names;
  for (const auto& n : flag_names(opt, true)) names += (names.empty() ? "" : ", ") + std::string("\\fB") + roff(n) + "\\fR";
  out << names;
  if (const std::string value = value_name(opt); !value.empty()) out << " \\fI" << roff(value) << "\\fR";
  if (repeatable(opt)) out << " ...";
  out << "\n" << roff(ended(opt.get_description())) << "\n";
}

void subcommand_section(std::ostream& out, const CLI::App& sub) {
  std::string synopsis = "gpsemu " + sub.get_name();
  for (const CLI::Option* p : options_of(sub, true)) synopsis += " " + positional_name(*p);
  synopsis += " [OPTIONS]";
  out << ".SS \"" << roff(synopsis) << "\"\n" << roff(sentence(sub.get_description())) << "\n";
  for (const CLI::Option* p : options_of(sub, true)) {
    out << ".TP\n\\fI" << roff(positional_name(*p)) << "\\fR" << (p->get_required() ? "" : " (optional)") << "\n"
        << roff(ended(p->get_description())) << "\n";
  }
  for (const CLI::Option* o : options_of(sub, false)) option_entry(out, *o);
}

}  // namespace

void write_man_page(std::ostream& out, const CLI::App& app, const std::string& version) {
  const auto subs = subcommands_of(app);
  std::string names;
  for (const CLI::App* s : subs) names += (names.empty() ? "" : ", ") + std::string("\\fB") + s->get_name() + "\\fR";

  out << ".\\\" gpsemu(1), generated from the command line gpsemu parses (tools/cli_doc): do not edit.\n"
      << ".TH GPSEMU 1 \"\" \"gpsemu " << roff(version) << "\" \"User Commands\"\n"
      << ".SH NAME\ngpsemu \\- hardware\\-in\\-the\\-loop GPS receiver emulator\n"
      << ".SH SYNOPSIS\n.B gpsemu\n[\\fIOPTIONS\\fR]\n.br\n.B gpsemu\n\\fISUBCOMMAND\\fR \\fIARGUMENTS\\fR "
         "[\\fIOPTIONS\\fR]\n"
      << ".SH DESCRIPTION\n" << roff(ended(app.get_description())) << "\n.PP\n"
      << "Every option except \\fB\\-\\-config\\fR is also a key of the TOML config file given with "
         "\\fB\\-\\-config\\fR \\fIFILE\\fR: the key is the long flag name without dashes, a repeatable option is "
         "an array. Flags override the file.\n"
      << ".SH OPTIONS\n"
      << ".TP\n\\fB\\-h\\fR, \\fB\\-\\-help\\fR\nPrint the options and exit (with a subcommand: its options).\n"
      << ".TP\n\\fB\\-\\-version\\fR\nPrint the version and exit.\n";
  for (const CLI::Option* o : options_of(app, false)) option_entry(out, *o);
  out << ".SH SUBCOMMANDS\n" << names
      << ". The options of \\fBgpsemu\\fR are accepted too, before or after the subcommand's name.\n";
  for (const CLI::App* s : subs) subcommand_section(out, *s);
  out << ".SH FILES\n"
      << ".TP\n\\fI/etc/gpsemu/NAME.toml\\fR\nThe config of the service instance \\fBgpsemu@NAME\\fR "
         "(\\fBsystemctl enable \\-\\-now gpsemu@NAME\\fR), which runs \\fBgpsemu \\-\\-config "
         "/etc/gpsemu/NAME.toml\\fR as the user \\fBgpsemu\\fR with the groups \\fBdialout\\fR (serial ports) "
         "and \\fBgpio\\fR (PPS on a GPIO line).\n"
      << ".TP\n\\fI/usr/share/doc/gpsemu/examples/car1.toml\\fR\nAn example config for a test bench.\n"
      << ".SH EXIT STATUS\n0 after a normal end (\\fB\\-\\-duration\\fR reached, or stopped by SIGINT or "
         "SIGTERM); 2 when a flag, value, config key, source or output is wrong, with one message naming "
         "it.\n"
      << ".SH SEE ALSO\n.BR gpsd (8),\n.BR systemctl (1)\n";
}

}  // namespace gpsemu::cli_doc
