// The real binary against real files and ptys: one destination named twice (stdout twice, one file
// by two names, --tee onto an output, one pty link) is refused naming both; a pty link served by a
// running gpsemu is refused, one left by a killed run is replaced.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace duplicate_outputs_test {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using test::read_file;
using test::write_file;

const std::vector<std::string> kFast = {GPSEMU_BINARY, "--fast", "--start-time", "2024-05-01T12:00:00Z",
                                        "--duration", "2"};

using test::contains;
using test::Result;
using test::run;

TEST(DuplicateOutputs, OneDestinationNamedTwiceIsRefusedNamingBoth) {
  const fs::path dir = test::scratch_dir("dupout", "twice");
  const fs::path a = write_file(dir / "a", "mine\n");
  fs::create_symlink("a", dir / "to-a");
  const std::string rel = "./" + fs::relative(a).string();  // the same file by a relative name
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> named;
  };
  const std::vector<Case> cases = {
      {{"--output", "stdout", "--output", "stdout"}, {"output 'stdout' and output 'stdout'"}},
      {{"--output", "file:" + a.string(), "--output", "file:" + rel},
       {"output 'file:" + a.string() + "'", "output 'file:" + rel + "'"}},
      {{"--output", "file:" + (dir / "to-a").string(), "--output", "file:" + a.string() + "?mode=append"},
       {"'file:" + (dir / "to-a").string() + "'", "'file:" + a.string() + "?mode=append'"}},
      {{"--output", "file:" + a.string(), "--tee", rel}, {"output 'file:" + a.string() + "'", "tee '" + rel + "'"}},
      {{"--output", "pty:" + (dir / "gps").string(), "--output", "pty:" + (dir / "." / "gps").string()}, {"pty link"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args[1]);
    const Result r = run(kFast, c.args);
    EXPECT_EQ(r.status, 2) << r.err;
    for (const std::string& name : c.named) EXPECT_TRUE(contains(r.err, name)) << r.err;
    EXPECT_TRUE(r.out.empty());
    EXPECT_EQ(read_file(a), "mine\n");
    EXPECT_FALSE(fs::exists(fs::symlink_status(dir / "gps")));
  }
  // Each receiver of a fleet likewise (receiver 1 is named).
  const Result fleet = run(kFast, {"--receivers", "2", "--output", "file:" + (dir / "r{i}").string(), "--tee",
                                   (dir / "r{i}").string()});
  EXPECT_EQ(fleet.status, 2) << fleet.err;
  EXPECT_TRUE(contains(fleet.err, "receiver 0")) << fleet.err;
}

TEST(DuplicateOutputs, ALiveGpsemusPtyLinkIsRefusedAStaleOneReplaced) {
  const fs::path dir = test::scratch_dir("dupout", "pty");
  const fs::path link = dir / "gps";
  test::Process first({GPSEMU_BINARY, "--duration", "60", "--output", "pty:" + link.string()});
  ASSERT_TRUE(first.wait_for_stderr("NMEA on", 10s)) << first.stderr_text();
  const fs::path first_pty = fs::read_symlink(link);

  // A second run with the same link (by another name): refused, the link and the pty left alone.
  const Result second = run({GPSEMU_BINARY, "--duration", "2"}, {"--output", "pty:" + (dir / "." / "gps").string()});
  EXPECT_EQ(second.status, 2) << second.err;
  EXPECT_TRUE(contains(second.err, "still running")) << second.err;
  EXPECT_TRUE(contains(second.err, first_pty.string())) << second.err;
  ASSERT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), first_pty);
  // A run with another link is not held back by the first one.
  const Result other = run({GPSEMU_BINARY, "--duration", "1"}, {"--output", "pty:" + (dir / "other").string()});
  EXPECT_EQ(other.status, 0) << other.err;

  // The first run crashes: its link is left dangling (or pointing at a reused pty) and is replaced.
  first.signal(SIGKILL);
  EXPECT_EQ(first.wait(10s), 128 + SIGKILL);
  ASSERT_TRUE(fs::is_symlink(link));
  test::Process third({GPSEMU_BINARY, "--duration", "60", "--output", "pty:" + link.string()});
  ASSERT_TRUE(third.wait_for_stderr("NMEA on", 10s)) << third.stderr_text();
  const fs::path third_pty = fs::read_symlink(link);
  EXPECT_TRUE(fs::exists(third_pty));
  third.signal(SIGTERM);
  EXPECT_EQ(third.wait(10s), 0) << third.stderr_text();
  EXPECT_FALSE(fs::exists(fs::symlink_status(link)));
}

}  // namespace duplicate_outputs_test
}  // namespace
}  // namespace gpsemu
