// Uses the installed package: a receiver from the CLI's keys, stepped with a truth that drives
// east at 2 m/s; prints the NMEA and checks a GGA with gpsemu::nmea's parser.
#include <cstdio>
#include <string>

#include "emulator/library/gpsemu.hpp"
#include "nmea/parse.hpp"

int main() {
  const gpsemu::api::Options options{{"start-time", {"2024-05-01T12:00:00Z"}}, {"rate", {"1"}},
                                     {"seed", {"7"}}, {"sentences", {"RMC,GGA"}},
                                     {"origin", {"43.0725,-89.4125,260"}}};
  gpsemu::api::Receiver receiver(options);
  int gga_ok = 0;
  for (int k = 0; k < 3; ++k) {
    const gpsemu::api::Epoch e = receiver.step_enu({2.0 * k, 0.0, 0.0}, {2.0, 0.0, 0.0});
    std::fputs(e.nmea.c_str(), stdout);
    std::size_t start = 0;
    while (start < e.nmea.size()) {
      const std::size_t end = e.nmea.find('\n', start);
      const std::string line = e.nmea.substr(start, end - start);
      start = end + 1;
      const auto sentence = gpsemu::nmea::parse_sentence(line);
      if (!sentence.ok()) continue;
      const auto gga = gpsemu::nmea::parse_gga(sentence.value());
      if (gga.ok()) ++gga_ok;
    }
  }
  std::printf("gpsemu %s: %d GGA parsed\n", gpsemu::api::version().c_str(), gga_ok);
  return gga_ok == 3 ? 0 : 1;
}
