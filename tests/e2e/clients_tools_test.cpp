// gpsemu's --fast file output read by real NMEA consumers from Debian (tools/setup
// --with-test-deps installs them; missing is a failure): python3-nmea2 parsing every sentence with
// checksums checked (tests/clients/pynmea2_check.py), also the NMEA part of a --protocol nmea+ubx
// stream, gpsdecode (gpsd's decoder, no daemon) and gpsbabel converting to GPX. Each is compared
// with what gpsemu wrote.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/model/time.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace clients_tools_test {

namespace fs = std::filesystem;
using namespace std::chrono;
using nlohmann::json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

fs::path temp_dir(const std::string& name) {
  const auto d = test::scratch_root() / fmt::format("gpsemu_clients_{}_{}", ::getpid(), name);
  fs::create_directories(d);
  return d;
}

using test::read_file;

bool installed(const std::string& program) {
  const bool ok = ::access(program.c_str(), X_OK) == 0;
  if (!ok) ADD_FAILURE() << program << " is missing: tools/setup --with-test-deps installs it";
  return ok;
}

/// Runs gpsemu --fast into `file` with the common scenario plus `args`.
void generate(const fs::path& file, std::vector<std::string> args) {
  std::vector<std::string> argv{GPSEMU_BINARY, "--fast", "--output", "file:" + file.string(), "--log-level", "warn"};
  argv.insert(argv.end(), args.begin(), args.end());
  const auto r = test::run(argv);
  ASSERT_EQ(r.status, 0) << r.err;
}

struct Position {
  double lat_deg = kNaN, lon_deg = kNaN;
};

/// The GGA positions of a file starting on `date`, by UTC time (ms since 1970) and in order; fixes only.
struct Emitted {
  std::map<std::int64_t, Position> by_time;
  std::vector<Position> in_order;
  int epochs = 0;
};

Emitted emitted_positions(const std::string& text, const std::string& date) {
  Emitted out;
  nmea::StreamReader reader;
  auto day_ms = duration_cast<milliseconds>(parse_iso8601_utc(date + "T00:00:00Z").time_since_epoch()).count();
  std::int64_t previous_ms = -1;
  for (const auto& s : reader.feed(text)) {
    if (s.type != "GGA") continue;
    const auto gga = nmea::parse_gga(s);
    EXPECT_TRUE(gga.ok());
    ++out.epochs;
    if (!gga.ok() || !gga->time_of_day) continue;
    if (gga->time_of_day->count() < previous_ms) day_ms += 86'400'000;  // past midnight
    previous_ms = gga->time_of_day->count();
    if (!gga.ok() || !gga->lat_deg || gga->quality == nmea::FixQuality::none) continue;
    const Position p{*gga->lat_deg, *gga->lon_deg};
    out.by_time[day_ms + gga->time_of_day->count()] = p;
    out.in_order.push_back(p);
  }
  return out;
}

std::int64_t utc_ms(const std::string& iso) {
  return duration_cast<milliseconds>(parse_iso8601_utc(iso).time_since_epoch()).count();
}

// Every sentence type, both NMEA versions and talkers, a cold start (no fix, 2-D) and an outage:
// every sentence parses with its checksum checked and the sentences of an epoch agree.
TEST(Pynmea2, ParsesEverySentenceOfEveryTypeWithChecksumsCheckedAndEpochsAgree) {
  const std::string python = "/usr/bin/python3";
  ASSERT_TRUE(installed(python));
  const auto probe = test::run({python, "-c", "import pynmea2"});
  ASSERT_EQ(probe.status, 0) << "python3-nmea2 is missing (tools/setup --with-test-deps installs it): " << probe.err;
  const auto dir = temp_dir("pynmea2");
  struct Case {
    std::string talker, version;
  };
  for (const Case& c : {Case{"GN", "4.1"}, Case{"GP", "2.3"}}) {
    const auto file = dir / fmt::format("{}_{}.nmea", c.talker, c.version);
    generate(file, {"--rate", "10", "--duration", "60", "--source", "sim:circle", "--talker", c.talker,
                    "--nmea-version", c.version, "--sentences", "RMC,VTG,GGA,GSA,GSV,GLL,GST,ZDA", "--cold-start",
                    "5,2", "--outage", "20+3", "--start-time", "2024-02-29T23:59:30Z", "--seed", "21"});
    const auto r = test::run({python, std::string(GPSEMU_SOURCE_DIR) + "/tests/clients/pynmea2_check.py", file.string()});
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    const json summary = json::parse(r.out);
    std::cout << "pynmea2 (" << c.talker << ", NMEA " << c.version << "): " << r.out;
    for (const char* type : {"RMC", "VTG", "GGA", "GLL", "GST", "ZDA"}) EXPECT_EQ(summary["counts"][type], 600) << type;
    EXPECT_GE(summary["counts"]["GSA"].get<int>(), 600);
    EXPECT_GE(summary["counts"]["GSV"].get<int>(), 600);
    EXPECT_EQ(summary["epochs"], 600);
    EXPECT_EQ(summary["fix_epochs"], 600 - 50 - 30);  // 5 s cold start and 3 s outage at 10 Hz
  }
  fs::remove_all(dir);
}

// --protocol nmea+ubx: pynmea2 parses the NMEA part (the UBX frames between the sentences taken
// out, their checksums checked), through a cold start and midnight; each epoch's NAV-PVT comes
// before its RMC, with the same time.
TEST(Pynmea2, ParsesTheNmeaPartOfAMixedNmeaAndUbxStream) {
  const std::string python = "/usr/bin/python3";
  ASSERT_TRUE(installed(python));
  const auto dir = temp_dir("pynmea2_ubx");
  const auto file = dir / "mixed.bin";
  generate(file, {"--protocol", "nmea+ubx", "--receiver", "ublox-m8n", "--rate", "10", "--duration", "30",
                  "--source", "sim:circle", "--cold-start", "3,1", "--start-time", "2024-02-29T23:59:45Z"});
  const auto r = test::run({python, std::string(GPSEMU_SOURCE_DIR) + "/tests/clients/pynmea2_check.py", "--ubx", file.string()});
  ASSERT_EQ(r.status, 0) << r.err << r.out;
  std::cout << "pynmea2 (nmea+ubx): " << r.out;
  const json summary = json::parse(r.out);
  for (const char* type : {"RMC", "VTG", "GGA", "GLL"}) EXPECT_EQ(summary["counts"][type], 300) << type;
  EXPECT_EQ(summary["epochs"], 300);
  EXPECT_EQ(summary["fix_epochs"], 300 - 30);  // 3 s without a fix at 10 Hz
  EXPECT_EQ(summary["ubx"]["01-07"], 300);       // NAV-PVT every epoch
  EXPECT_EQ(summary["pvt_before_rmc"], 300);
  fs::remove_all(dir);
}

// gpsd's decoder without the daemon: a TPV for every epoch with a fix, at the emitted position;
// SKY with the satellites in view and used; GST with the error estimates.
TEST(Gpsdecode, ReportsEveryFixAtTheEmittedPositionWithSkyAndGst) {
  ASSERT_TRUE(installed("/usr/bin/gpsdecode"));
  const auto dir = temp_dir("gpsdecode");
  const auto file = dir / "run.nmea";
  generate(file, {"--rate", "5", "--duration", "60", "--source", "sim:circle", "--sentences",
                  "RMC,VTG,GGA,GSA,GSV,GLL,GST,ZDA", "--outage", "30+4", "--start-time", "2024-06-30T23:59:30Z",
                  "--seed", "22"});
  const Emitted emitted = emitted_positions(read_file(file), "2024-06-30");
  ASSERT_EQ(emitted.epochs, 300);
  ASSERT_EQ(emitted.by_time.size(), 280u);
  const auto r = test::run({"/bin/sh", "-c", "exec /usr/bin/gpsdecode < '" + file.string() + "'"});
  ASSERT_EQ(r.status, 0) << r.err;
  int mode3 = 0, sky = 0, gst = 0, unmatched = 0;
  double worst_deg = 0.0;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    const json j = json::parse(line, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << line;
    if (j["class"] == "SKY" && j.contains("satellites")) {
      ++sky;
      EXPECT_LE(j.value("uSat", 0), j.value("nSat", 0)) << line;
    } else if (j["class"] == "GST") {
      if (j.value("lat", 0.0) == 0.0) continue;  // the outage's empty GST
      ++gst;
      // Reported accuracy = DOP x UERE (an M8N's 1.6 m): HDOP x 1.6 / sqrt 2 per axis (its sky's
      // HDOP 0.5-1.2: 0.57-1.36 m), never below the 0.3 m floor; range RMS = the UERE.
      EXPECT_EQ(j.value("lat", 0.0), j.value("lon", 0.0)) << line;
      EXPECT_GE(j.value("lat", 0.0), 0.3) << line;
      EXPECT_LE(j.value("lat", 0.0), 1.4) << line;
      EXPECT_NEAR(j.value("rms", 0.0), 1.6, 0.01) << line;
    } else if (j["class"] == "TPV" && j.value("mode", 0) == 3) {
      ++mode3;
      const auto e = emitted.by_time.find(utc_ms(j["time"].get<std::string>()));
      if (e == emitted.by_time.end()) {
        ++unmatched;
        continue;
      }
      worst_deg = std::max({worst_deg, std::fabs(j["lat"].get<double>() - e->second.lat_deg),
                            std::fabs(j["lon"].get<double>() - e->second.lon_deg)});
    }
  }
  std::cout << fmt::format("gpsdecode: {} mode-3 TPVs for {} fix epochs, {} unmatched, worst difference {:.1e} deg; "
                           "{} SKY, {} GST\n", mode3, emitted.by_time.size(), unmatched, worst_deg, sky, gst);
  EXPECT_GE(mode3, static_cast<int>(emitted.by_time.size()) - 2) << "gpsd learns the cycle on the first epoch";
  EXPECT_LE(mode3, static_cast<int>(emitted.by_time.size()));
  EXPECT_EQ(unmatched, 0) << "a 3-D fix reported during the outage or at a time never written";
  EXPECT_LT(worst_deg, 1e-8);
  EXPECT_GE(sky, 250);
  EXPECT_GE(gst, 250);
  fs::remove_all(dir);
}

/// The trackpoints of a GPX file: (time in ms, lat, lon), in order.
struct TrackPoint {
  std::optional<std::int64_t> time_ms;
  Position position;
};

std::vector<TrackPoint> gpx_points(const std::string& gpx) {
  std::vector<TrackPoint> out;
  static const std::regex point(R"re(<trkpt lat="([-0-9.]+)" lon="([-0-9.]+)">([\s\S]*?)</trkpt>)re");
  static const std::regex time(R"re(<time>([^<]+)</time>)re");
  for (auto it = std::sregex_iterator(gpx.begin(), gpx.end(), point); it != std::sregex_iterator(); ++it) {
    TrackPoint p;
    p.position = {std::stod((*it)[1]), std::stod((*it)[2])};
    const std::string body = (*it)[3];
    std::smatch t;
    if (std::regex_search(body, t, time)) p.time_ms = utc_ms(t[1]);
    out.push_back(p);
  }
  return out;
}

std::vector<TrackPoint> gpsbabel_to_gpx(const fs::path& nmea, const std::string& input_options) {
  const fs::path gpx = nmea.string() + ".gpx";
  const auto r = test::run({"/usr/bin/gpsbabel", "-i", "nmea" + input_options, "-f", nmea.string(), "-o", "gpx", "-F",
                            gpx.string()});
  EXPECT_EQ(r.status, 0) << r.err;
  return gpx_points(read_file(gpx));
}

// With ZDA in the set and gpsbabel told to take positions from GGA (gprmc=0), every trackpoint is
// an emitted fix at its own time. gpsbabel's default pairing assumes GGA before RMC (SiRF order):
// with u-blox order (RMC first) it stamps each GGA with the next epoch's RMC time, so that mode
// is checked on the sequence of positions only (see the README section).
TEST(Gpsbabel, GpxTrackpointsAreTheEmittedPositions) {
  ASSERT_TRUE(installed("/usr/bin/gpsbabel"));
  const auto dir = temp_dir("gpsbabel");
  const auto file = dir / "run.nmea";
  generate(file, {"--rate", "5", "--duration", "60", "--source", "sim:circle", "--sentences",
                  "RMC,VTG,GGA,GSA,GSV,GLL,ZDA", "--cold-start", "3,2", "--start-time", "2024-06-30T23:59:30Z",
                  "--seed", "23", "--resolution", "7"});
  const Emitted emitted = emitted_positions(read_file(file), "2024-06-30");
  ASSERT_EQ(emitted.by_time.size(), 300u - 15u);

  const auto timed = gpsbabel_to_gpx(file, ",gprmc=0");
  ASSERT_EQ(timed.size(), emitted.by_time.size());
  double worst_deg = 0.0;
  for (const TrackPoint& p : timed) {
    ASSERT_TRUE(p.time_ms.has_value());
    const auto e = emitted.by_time.find(*p.time_ms);
    ASSERT_NE(e, emitted.by_time.end()) << "a trackpoint at a time without an emitted fix: " << *p.time_ms;
    worst_deg = std::max({worst_deg, std::fabs(p.position.lat_deg - e->second.lat_deg),
                          std::fabs(p.position.lon_deg - e->second.lon_deg)});
  }
  EXPECT_LT(worst_deg, 1e-8);  // GPX has 9 decimals; 7 decimals of minutes are 1.7e-9 degrees

  const auto plain = gpsbabel_to_gpx(file, "");
  // The plain conversion may start with an RMC-only point and ends without the last GGA (no RMC
  // follows it); in between, the GGA positions in order.
  ASSERT_GE(plain.size() + 1, emitted.in_order.size());
  ASSERT_LE(plain.size(), emitted.in_order.size() + 1);
  const auto same = [](const Position& a, const Position& b) {
    return std::fabs(a.lat_deg - b.lat_deg) < 1e-8 && std::fabs(a.lon_deg - b.lon_deg) < 1e-8;
  };
  const std::size_t skip = same(plain[0].position, emitted.in_order[0]) ? 0 : 1;
  const std::size_t compared = std::min(plain.size() - skip, emitted.in_order.size());
  EXPECT_GE(compared + 1, emitted.in_order.size());
  double worst_plain_deg = 0.0;
  for (std::size_t i = 0; i < compared; ++i) {
    worst_plain_deg = std::max({worst_plain_deg, std::fabs(plain[i + skip].position.lat_deg - emitted.in_order[i].lat_deg),
                                std::fabs(plain[i + skip].position.lon_deg - emitted.in_order[i].lon_deg)});
  }
  EXPECT_LT(worst_plain_deg, 1e-8);
  std::cout << fmt::format("gpsbabel: {} trackpoints (gprmc=0) for {} fixes, worst difference {:.1e} deg; plain: {} "
                           "trackpoints, worst {:.1e} deg in sequence\n", timed.size(), emitted.by_time.size(),
                           worst_deg, plain.size(), worst_plain_deg);
  fs::remove_all(dir);
}

}  // namespace clients_tools_test
}  // namespace
}  // namespace gpsemu
