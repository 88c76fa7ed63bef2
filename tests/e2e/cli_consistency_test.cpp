// End to end (issue 18, consistency): the real gpsemu binary at start-up. Every start-up error is
// one line "gpsemu: ..." with exit status 2, whatever raised it (the command-line parser, the
// configuration, opening an output, a subcommand); --start-time takes only what its help says (a
// UTC time ending in Z); --config takes regular files only (a FIFO must not block, a device must
// not read as empty); `gpsemu replay --help` lists the options a replay reads; every talker the
// --talker help names is accepted and used.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <regex>
#include <string>
#include <vector>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace cli_consistency_test {

using namespace std::chrono;

using test::Result;

/// gpsemu ARGS, run to completion.
test::Result run(const std::vector<std::string>& args) { return test::run({GPSEMU_BINARY}, args); }

/// Exit status 2 and exactly one line on stderr, "gpsemu: " then text matching `what`.
void expect_one_line_error(const std::vector<std::string>& args, const std::string& what) {
  const Result r = run(args);
  std::string shown;
  for (const auto& a : args) shown += a + " ";
  EXPECT_EQ(r.status, 2) << shown << "\n" << r.err;
  EXPECT_TRUE(std::regex_match(r.err, std::regex("gpsemu: [^\n]*\n"))) << shown << ": not one line:\n" << r.err;
  EXPECT_TRUE(std::regex_search(r.err, std::regex(what))) << shown << ": " << r.err;
}

TEST(CliConsistency, EveryStartUpErrorIsOneLineStartingWithGpsemu) {
  const auto dir = test::scratch_dir("cli", "errors");
  const std::string fast[] = {"--fast", "--duration", "1"};
  // The command-line parser (CLI11), a value (the option table), an output that cannot open (the
  // runner), a subcommand's input (replay), a replay-only flag without replay.
  expect_one_line_error({"--bogus"}, "--bogus.*gpsemu --help");
  expect_one_line_error({"--rate"}, "rate");
  expect_one_line_error({"--rate", "0"}, "--rate: rate must be from 0.1 to 50");
  expect_one_line_error({"--output", "serial:/nonexistent/tty", fast[0], fast[1], fast[2]}, "/nonexistent/tty");
  expect_one_line_error({"--output", "file:" + (dir / "no" / "such.nmea").string(), fast[0], fast[1], fast[2]},
                        "such.nmea");
  expect_one_line_error({"replay", (dir / "missing.nmea").string(), "--output", "stdout"},
                        "cannot open NMEA log .*missing.nmea");
  expect_one_line_error({"--speed", "10", fast[0], fast[1], fast[2]}, "--speed applies to 'gpsemu replay LOG' only");
}

TEST(CliConsistency, StartTimeNeedsTheUtcDesignatorAndRefusesOffsets) {
  expect_one_line_error({"--start-time", "2024-05-01T12:00:00", "--fast", "--duration", "1", "--output", "stdout"},
                        "'2024-05-01T12:00:00': end the time with Z.*e\\.g\\. 2024-05-01T12:00:00Z");
  expect_one_line_error({"--start-time", "2024-05-01T12:00:00+02:00", "--fast", "--duration", "1"},
                        "only UTC times are accepted");
  // The same in a config file: a TOML local date-time is not UTC.
  const auto dir = test::scratch_dir("cli", "start_time");
  const auto local = test::write_file(dir / "local.toml", "start-time = 2024-05-01T12:00:00\n");
  expect_one_line_error({"--config", local.string(), "--fast", "--duration", "1"}, "local.toml:1: key 'start-time'.*Z");
  // What the help documents works, from the flag and from a TOML date-time.
  const auto utc = test::write_file(dir / "utc.toml", "start-time = 2024-05-01T12:00:00Z\n");
  for (const std::vector<std::string>& given : {std::vector<std::string>{"--start-time", "2024-05-01T12:00:00Z"},
                                                std::vector<std::string>{"--config", utc.string()}}) {
    std::vector<std::string> args = given;
    for (const char* a : {"--fast", "--duration", "1", "--output", "stdout", "--log-level", "warn"}) args.push_back(a);
    const Result r = run(args);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("$GNRMC,120000.00,A"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(",010524,"), std::string::npos) << r.out;
  }
}

TEST(CliConsistency, ConfigMustBeARegularFileAndAFifoNeverBlocks) {
  const auto dir = test::scratch_dir("cli", "config_kind");
  const auto fifo = dir / "config.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto started = steady_clock::now();
  expect_one_line_error({"--config", fifo.string(), "--fast", "--duration", "1"}, "config.fifo: a FIFO; give a regular");
  EXPECT_LT(steady_clock::now() - started, seconds(10)) << "gpsemu waited on the FIFO";
  expect_one_line_error({"--config", "/dev/null", "--fast", "--duration", "1"}, "/dev/null: a device");
  expect_one_line_error({"--config", dir.string(), "--fast", "--duration", "1"}, "a directory");
  expect_one_line_error({"--config", (dir / "missing.toml").string()}, "missing.toml: No such file");
}

TEST(CliConsistency, ReplayHelpListsTheOptionsAReplayReads) {
  const Result r = run({"replay", "--help"});
  EXPECT_EQ(r.status, 0);
  for (const char* flag : {"--speed K", "--loop", "--from WHEN", "--to WHEN", "--retime", "--output SPEC", "--tee FILE",
                           "--start-time ISO8601", "--duration S", "--fast", "Example: gpsemu replay"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag << " missing from:\n" << r.out;
  }
}

TEST(CliConsistency, EveryTalkerTheHelpNamesIsAcceptedAndUsed) {
  const Result help = run({"--help"});
  for (const std::string talker : {"GP", "GN", "GL", "GA", "BD"}) {
    EXPECT_TRUE(std::regex_search(help.out, std::regex("--talker ID[^\n]*\\b" + talker + "\\b"))) << talker;
    const Result r = run({"--talker", talker, "--fast", "--duration", "1", "--output", "stdout", "--log-level", "warn"});
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("$" + talker + "GGA,"), std::string::npos) << talker << ": " << r.out;
  }
  expect_one_line_error({"--talker", "XX"}, "talker must be one of GP, GN, GL, GA, BD, got 'XX'");
}

}  // namespace cli_consistency_test
}  // namespace
}  // namespace gpsemu
