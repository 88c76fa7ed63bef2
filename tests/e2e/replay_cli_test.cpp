// `gpsemu replay` and the clock/tee options on the command line: every bad input at start-up is
// one clear message and exit status 2 (missing or empty log, a log without NMEA, bad --speed,
// --from/--to, clocks replay does not use, an unwritable --tee), and the help lists the options.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace replay_cli_test {

namespace fs = std::filesystem;

fs::path write(const std::string& name, const std::string& text) {
  auto d = test::scratch_root() / fmt::format("gpsemu_replay_cli_{}", ::getpid());
  fs::create_directories(d);
  return test::write_file(d / name, text);
}

/// A two-epoch 1 Hz log.
fs::path good_log() {
  return write("good.nmea",
               "$GPGGA,120000.00,4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,*75\r\n"
               "$GPGGA,120001.00,4304.35011,N,08924.75026,W,1,11,0.92,260.1,M,0.0,M,,*76\r\n");
}

void expect_error(const std::vector<std::string>& args, const std::string& message) {
  std::vector<std::string> argv{GPSEMU_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  const auto r = test::run(argv, std::chrono::seconds(30));
  EXPECT_EQ(r.status, 2) << fmt::format("{}", fmt::join(args, " ")) << "\n" << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << "expected '" << message << "' in:\n" << r.err;
}

TEST(ReplayCli, BadLogsExitWithStatus2NamingTheFile) {
  expect_error({"replay", "/nonexistent/drive.nmea"}, "cannot open NMEA log '/nonexistent/drive.nmea': No such file");
  const auto empty = write("empty.nmea", "");
  expect_error({"replay", empty.string()}, fmt::format("NMEA log '{}' holds no valid NMEA sentence (0 bytes", empty.string()));
  const auto junk = write("junk.nmea", std::string("\xb5\x62\x01\x07garbage\r\n$GPGGA,1*00\r\n# only a comment\n", 38));
  expect_error({"replay", junk.string()}, "holds no valid NMEA sentence (38 bytes: 1 bad checksums");
  expect_error({"replay"}, "log is required");
}

TEST(ReplayCli, BadOptionsExitWithStatus2NamingTheOption) {
  const std::string log = good_log().string();
  expect_error({"replay", log, "--speed", "0"}, "--speed: speed must be from 0.1 to 100, got 0");
  expect_error({"replay", log, "--speed", "200"}, "--speed: speed must be from 0.1 to 100");
  expect_error({"replay", log, "--speed", "fast"}, "--speed: speed expects a number");
  expect_error({"replay", log, "--from", "noon"}, "--from: from: expected a time of day hh:mm:ss[.ss]");
  expect_error({"replay", log, "--from", "13:00:00", "--output", "stdout"},
               "--from: 13:00:00.000: no epoch at or after it in the log (its times run from 12:00:00.000 to 12:00:01.000)");
  expect_error({"replay", log, "--to", "2", "--output", "stdout"}, "--to: epoch 2 is past the end: the log has 2 epochs (0..1)");
  expect_error({"replay", log, "--from", "1", "--to", "0", "--output", "stdout"}, "comes before the first one selected");
  expect_error({"replay", log, "--clock", "scaled:2", "--output", "stdout"},
               "replay paces by the log's own times: use --speed K (or --fast), not --clock scaled:2");
  expect_error({"replay", log, "--output", "stdout", "--tee", "/nonexistent/dir/session.tee"}, "/nonexistent/dir/session.tee");
  expect_error({"replay", log, "--output", "bogus:thing"}, "bogus:thing");
  expect_error({"replay", log, "--loop", "--fast", "--output", "stdout"},
               "--loop with --fast would never end: give --duration S");
}

TEST(ReplayCli, HelpListsTheReplayAndClockOptions) {
  const auto r = test::run({GPSEMU_BINARY, "--help"});
  EXPECT_EQ(r.status, 0);
  for (const char* option : {"--clock CLOCK", "--speed K", "--loop", "--from WHEN", "--to WHEN", "--retime", "--tee FILE",
                             "replay:FILE.csv", "replay"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  }
}

TEST(ReplayCli, AGoodLogRunsToTheEndAndExits0) {
  const auto r = test::run({GPSEMU_BINARY, "replay", good_log().string(), "--fast", "--output", "stdout"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "$GPGGA,120000.00,4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,*75\r\n"
                   "$GPGGA,120001.00,4304.35011,N,08924.75026,W,1,11,0.92,260.1,M,0.0,M,,*76\r\n");
}

}  // namespace replay_cli_test
}  // namespace
}  // namespace gpsemu
