// Trajectory replay, --source replay:FILE.csv (emulator/sources/trajectory_source.hpp): the CSV
// reader (columns, time bases, errors naming file:line), interpolation and velocity, and end to
// end through the binary: the same drive and seed give byte-identical NMEA, another seed or noise
// model other NMEA, no noise the file's positions; the run ends with the trajectory.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "emulator/sources/trajectory_source.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::sources {
namespace {
namespace replay_trajectory_test {

namespace fs = std::filesystem;
using namespace std::chrono;

const Geodetic kOrigin{43.0725, -89.4125, 260.0};
const UtcNs kStart = parse_iso8601_utc("2024-05-01T12:00:00Z");
UtcNs at_s(double s) { return kStart + nanoseconds{std::llround(s * 1e9)}; }

fs::path temp_dir() {
  static const fs::path dir = test::scratch_dir("traj", "e2e");  // once a process: files stay
  return dir;
}

fs::path write(const std::string& name, const std::string& text) {
  return test::write_file(temp_dir() / name, text);
}

using test::read_file;

/// A drive: east at 2 m/s for 10 s, then north at 1 m/s for 10 s, rows every second.
std::string drive_csv() {
  std::string csv = "# a recorded drive\ntime_s, east_m, north_m, up_m\n";
  for (int i = 0; i <= 20; ++i) {
    const double e = i <= 10 ? 2.0 * i : 20.0;
    const double n = i <= 10 ? 0.0 : 1.0 * (i - 10);
    csv += fmt::format("{}, {}, {}, 0.5\n", i, e, n);
  }
  return csv;
}

TEST(TrajectoryCsv, LocalColumnsFromTheFirstEpochInterpolateWithTrackVelocity) {
  const LocalFrame frame(kOrigin);
  TrajectorySource source(read_trajectory_csv(write("drive.csv", drive_csv()), frame, kStart));
  EXPECT_FALSE(source.truth_at(at_s(-0.1))) << "before the first row: no fix";
  const auto a = source.truth_at(at_s(2.5));
  ASSERT_TRUE(a);
  EXPECT_NEAR(a->position_m.east_m, 5.0, 1e-9);
  EXPECT_NEAR(a->position_m.up_m, 0.5, 1e-9);
  EXPECT_NEAR(a->velocity_mps.east_m, 2.0, 1e-9);
  EXPECT_NEAR(a->velocity_mps.north_m, 0.0, 1e-9);
  const auto b = source.truth_at(at_s(12.25));
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->position_m.north_m, 2.25, 1e-9);
  EXPECT_NEAR(b->velocity_mps.north_m, 1.0, 1e-9);
  const auto end = source.truth_at(at_s(20.0));
  ASSERT_TRUE(end);
  EXPECT_NEAR(end->position_m.north_m, 10.0, 1e-9);
  EXPECT_FALSE(source.ended_at(at_s(20.0)));
  EXPECT_TRUE(source.ended_at(at_s(20.001)));
  EXPECT_FALSE(source.truth_at(at_s(20.001)));
}

TEST(TrajectoryCsv, UtcGeodeticColumnsWithVelocityAndXyzAliases) {
  const LocalFrame frame(kOrigin);
  const std::string csv =
      "utc,lat_deg,lon_deg,alt_m,ve_mps,vn_mps\n"
      "2024-05-01T12:00:10Z,43.0725,-89.4125,262.0,1.0,0.0\n"
      "2024-05-01T12:00:12Z,43.0725,-89.41225,262.0,3.0,0.0\n";
  TrajectorySource source(read_trajectory_csv(write("utc.csv", csv), frame, kStart));
  EXPECT_FALSE(source.truth_at(at_s(9.0)));
  const auto mid = source.truth_at(at_s(11.0));
  ASSERT_TRUE(mid);
  const Enu far = frame.to_enu({43.0725, -89.41225, 262.0});
  EXPECT_NEAR(mid->position_m.east_m, far.east_m / 2.0, 1e-6);
  EXPECT_NEAR(mid->position_m.up_m, 2.0, 1e-3);
  EXPECT_NEAR(mid->velocity_mps.east_m, 2.0, 1e-9) << "velocity columns interpolated";
  const std::string xyz = "time_s,x_m,y_m,z_m\n0,1,2,3\n1,2,3,4\n";
  TrajectorySource alias(read_trajectory_csv(write("xyz.csv", xyz), frame, kStart));
  EXPECT_NEAR(alias.truth_at(at_s(0.5))->position_m.north_m, 2.5, 1e-9);
}

TEST(TrajectoryCsv, BadFilesAreRefusedNamingFileAndLine) {
  const LocalFrame frame(kOrigin);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"time_s,east_m,north_m\n0,0,0\n1,x,0\n", "bad1.csv:3: column east_m: 'x' is not a number"},
      {"time_s,east_m,north_m\n0,0,0\n1,1\n", "bad2.csv:3: 2 values where the header names 3"},
      {"time_s,east_m,north_m\n0,0,0\n0,1,0\n", "bad3.csv:3: time 0 is not after the previous row's"},
      {"time_s,east_m,nort_m\n0,0,0\n", "bad4.csv:1: unknown column 'nort_m'"},
      {"east_m,north_m\n0,0\n", "bad5.csv:1: the header must name exactly one time column"},
      {"time_s,lat_deg,east_m,north_m\n", "bad6.csv:1: the header must name lat_deg,lon_deg[,alt_m] or east_m,north_m"},
      {"time_s,lat_deg,lon_deg\n0,91,0\n1,0,0\n", "bad7.csv:2: latitude 91 outside [-90, 90]"},
      {"utc,east_m,north_m\n2024-05-01T12:00:00Z,0,0\nyesterday,1,1\n", "bad8.csv:3: column utc:"},
      {"time_s,east_m,north_m,ve_mps\n0,0,0,1\n", "bad9.csv:1: velocity needs both ve_mps and vn_mps"},
      {"time_s,east_m,north_m\n0,0,0\n", "has 1 rows: at least 2 are needed"},
      {"", "is empty (no header)"},
      // Beyond any real trajectory (infinite interpolated positions and speeds before the limits).
      {"time_s,east_m,north_m\n0,1e300,0\n1,-1e300,0\n", "bad12.csv:2: column east_m: 1e+300 is outside +-1e+07 metres"},
      {"time_s,lat_deg,lon_deg,alt_m\n0,0,0,2e6\n", "bad13.csv:2: column alt_m: 2000000 is outside [-10000, 1e+06] metres"},
      {"time_s,east_m,north_m,ve_mps,vn_mps\n0,0,0,0,-2e4\n", "bad14.csv:2: column vn_mps: -20000 is outside +-10000 m/s"},
  };
  int i = 0;
  for (const auto& [text, message] : cases) {
    const auto path = write(fmt::format("bad{}.csv", ++i), text);
    try {
      (void)read_trajectory_csv(path, frame, kStart);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW((void)read_trajectory_csv(temp_dir() / "missing.csv", frame, kStart), std::runtime_error);
}

TEST(TrajectoryCsv, ReadsFromAStreamNamedInMessages) {
  const LocalFrame frame(kOrigin);
  std::istringstream good("time_s,east_m,north_m\n0,0,0\n2,4,0\n");
  const Trajectory t = read_trajectory_csv(good, "drive.csv", frame, kStart);
  EXPECT_EQ(t.path, "drive.csv");
  ASSERT_EQ(t.points.size(), 2u);
  EXPECT_EQ(t.points[1].time, kStart + std::chrono::seconds(2));
  std::istringstream bad("time_s,east_m,north_m\n0,0,0\n");
  try {
    (void)read_trajectory_csv(bad, "drive.csv", frame, kStart);
    ADD_FAILURE() << "accepted one row";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "trajectory file 'drive.csv' has 1 rows: at least 2 are needed");
  }
}

// ---- through the binary ------------------------------------------------------------------------

std::string run_drive(const fs::path& csv, const std::string& out_name, std::vector<std::string> extra) {
  const auto out = temp_dir() / out_name;
  std::vector<std::string> args{GPSEMU_BINARY, "--source", "replay:" + csv.string(), "--fast", "--start-time",
                                "2024-05-01T12:00:00Z", "--rate", "5", "--output", "file:" + out.string(),
                                "--log-level", "warn"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto r = test::run(args);
  EXPECT_EQ(r.status, 0) << r.err;
  return read_file(out);
}

TEST(TrajectoryReplay, SameDriveAndSeedGiveByteIdenticalNmeaOtherSeedsAndModelsDiffer) {
  const auto csv = write("drive_e2e.csv", drive_csv());
  const std::string a = run_drive(csv, "a.nmea", {"--seed", "7", "--noise", "gauss-markov"});
  const std::string b = run_drive(csv, "b.nmea", {"--seed", "7", "--noise", "gauss-markov"});
  const std::string c = run_drive(csv, "c.nmea", {"--seed", "8", "--noise", "gauss-markov"});
  const std::string d = run_drive(csv, "d.nmea", {"--seed", "7", "--noise", "cgrw"});
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b) << "same drive, same seed: byte-identical";
  EXPECT_NE(a, c) << "another seed";
  EXPECT_NE(a, d) << "another noise model";
  // 20 s at 5 Hz, both ends included: the run stops with the trajectory.
  std::size_t rmc = 0;
  for (std::size_t at = a.find("$GNRMC,"); at != std::string::npos; at = a.find("$GNRMC,", at + 1)) ++rmc;
  EXPECT_EQ(rmc, 101u);
  EXPECT_NE(a.find("$GNRMC,120020.00,A,"), std::string::npos);
  EXPECT_EQ(a.find("$GNRMC,120020.20,"), std::string::npos);
}

TEST(TrajectoryReplay, WithoutNoiseTheReceiverReportsTheFilesPositionsAndSpeeds) {
  const LocalFrame frame(kOrigin);
  const auto csv = write("drive_none.csv", drive_csv());
  const std::string nmea = run_drive(csv, "none.nmea", {"--noise", "none", "--sentences", "GGA,RMC"});
  int checked = 0;
  for (std::size_t at = nmea.find("$GNGGA,"); at != std::string::npos; at = nmea.find("$GNGGA,", at + 1)) {
    const std::string line = nmea.substr(at, nmea.find('\n', at) - at);
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    const double t = std::stod(f[1].substr(4)) + 60.0 * std::stod(f[1].substr(2, 2)) - 0.0;  // seconds after 12:00
    const double lat = std::stod(f[2].substr(0, 2)) + std::stod(f[2].substr(2)) / 60.0;
    const double lon = -(std::stod(f[4].substr(0, 3)) + std::stod(f[4].substr(3)) / 60.0);
    const Enu got = frame.to_enu({lat, lon, std::stod(f[9])});
    const double e = t <= 10 ? 2.0 * t : 20.0, n = t <= 10 ? 0.0 : t - 10.0;
    EXPECT_NEAR(got.east_m, e, 0.02) << line;
    EXPECT_NEAR(got.north_m, n, 0.02) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 101);
  // RMC speed: 2 m/s = 3.888 kn on the first leg.
  EXPECT_NE(nmea.find("$GNRMC,120005.00,A,"), std::string::npos);
  const auto rmc = nmea.substr(nmea.find("$GNRMC,120005.00,A,"), 80);
  EXPECT_NE(rmc.find(",3.888,"), std::string::npos) << rmc;
}

TEST(TrajectoryReplay, ABadCsvLineExitsWithStatus2NamingFileAndLine) {
  const auto csv = write("bad_line.csv", "time_s,east_m,north_m\n0,0,0\n1,2,zero\n");
  const auto r = test::run({GPSEMU_BINARY, "--source", "replay:" + csv.string(), "--fast", "--output", "stdout"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(csv.string() + ":3: column north_m: 'zero' is not a number"), std::string::npos) << r.err;
  const auto missing = test::run({GPSEMU_BINARY, "--source", "replay:/nonexistent/drive.csv", "--fast"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("cannot open trajectory file '/nonexistent/drive.csv'"), std::string::npos) << missing.err;
  const auto past = test::run({GPSEMU_BINARY, "--source", "replay:" + write("past.csv", "utc,east_m,north_m\n"
                               "2001-01-01T00:00:00Z,0,0\n2001-01-01T00:00:01Z,1,0\n").string(), "--fast"});
  EXPECT_EQ(past.status, 2);
  EXPECT_NE(past.err.find("before the first epoch"), std::string::npos) << past.err;
}

}  // namespace replay_trajectory_test
}  // namespace
}  // namespace gpsemu::sources
