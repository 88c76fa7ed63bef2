// gpsemu-package-doc: the man page and the bash completion of the Debian package, written from the
// very CLI11 application main() parses (gpsemu::make_command_line()), as docs/cli.md is.
//   gpsemu-package-doc --format man|bash [FILE]     (stdout without FILE)
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "emulator/app/command_line.hpp"
#include "tools/cli_doc/completion.hpp"
#include "tools/cli_doc/man_page.hpp"

int main(int argc, char** argv) {
  const std::string format = argc >= 3 && std::string(argv[1]) == "--format" ? argv[2] : "";
  if ((format != "man" && format != "bash") || argc > 4) {
    std::cerr << "usage: gpsemu-package-doc --format man|bash [FILE]  (stdout without FILE)\n";
    return 2;
  }
  const auto command_line = gpsemu::make_command_line();
  std::ostringstream text;
  if (format == "man") gpsemu::cli_doc::write_man_page(text, command_line->app, GPSEMU_VERSION);
  else gpsemu::cli_doc::write_bash_completion(text, command_line->app);
  if (argc == 3) {
    std::cout << text.str();
    return 0;
  }
  std::ofstream file(argv[3], std::ios::binary);
  file << text.str();
  if (!file.flush()) {
    std::cerr << "gpsemu-package-doc: cannot write " << argv[3] << "\n";
    return 1;
  }
  return 0;
}
