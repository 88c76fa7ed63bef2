// The real binary against real files: a start-up that fails (a serial device, tee, tcp address or
// PPS line that cannot be opened) leaves every output path as it was; file:PATH?mode=append adds,
// mode=new refuses an existing file; file: writes through a symlink.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace output_safety_test {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using test::read_file;
using test::write_file;

const std::vector<std::string> kFast = {GPSEMU_BINARY, "--fast", "--start-time", "2024-05-01T12:00:00Z",
                                        "--duration", "2"};

using test::contains;
using test::Result;
using test::run;

TEST(OutputSafety, AFailedStartUpLeavesEveryPathAsItWas) {
  const fs::path dir = test::scratch_dir("outsafe", "failed");
  const fs::path kept = write_file(dir / "p.nmea", "existing\n");
  const fs::path tee = write_file(dir / "tee.txt", "tee before\n");
  const fs::path appended = write_file(dir / "a.nmea", "append before\n");
  const fs::path missing = dir / "m.nmea";
  const fs::path other = write_file(dir / "x.nmea", "x\n");
  const std::vector<std::string> files = {"--output", "file:" + kept.string(), "--output",
                                          "file:" + appended.string() + "?mode=append", "--output",
                                          "file:" + missing.string()};
  struct Case {
    std::vector<std::string> extra;
    std::string named;  ///< in the error message
    bool realtime = false;
  };
  const std::vector<Case> cases = {
      {{"--output", "serial:/nonexistent", "--tee", tee.string()}, "/nonexistent"},
      {{"--tee", (dir / "no-dir" / "t.txt").string()}, "no-dir"},
      {{"--output", "tcp:nonexistent.invalid:5000", "--tee", tee.string()}, "nonexistent.invalid"},
      {{"--pps", "gpio:gpiochip99:3", "--tee", tee.string()}, "gpiochip99", true},
      {{"--output", "file:" + (dir / "n.nmea").string(), "--output", "file:" + other.string() + "?mode=new"},
       other.string() + " already exists"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.named);
    std::vector<std::string> args = files;
    args.insert(args.end(), c.extra.begin(), c.extra.end());
    const Result r = c.realtime ? run({GPSEMU_BINARY, "--duration", "2"}, args) : run(kFast, args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(contains(r.err, c.named)) << r.err;
    EXPECT_EQ(read_file(kept), "existing\n");
    EXPECT_EQ(read_file(tee), "tee before\n");
    EXPECT_EQ(read_file(appended), "append before\n");
    EXPECT_FALSE(fs::exists(missing));
    EXPECT_EQ(read_file(other), "x\n");
    EXPECT_FALSE(fs::exists(dir / "n.nmea"));
  }
  // The same outputs without the failing one: truncated, appended to, created.
  const Result ok = run(kFast, files);
  ASSERT_EQ(ok.status, 0) << ok.err;
  const std::string epochs = read_file(kept);
  EXPECT_TRUE(epochs.rfind("$G", 0) == 0) << epochs;
  EXPECT_EQ(read_file(missing), epochs);
  EXPECT_EQ(read_file(appended), "append before\n" + epochs);
}

TEST(OutputSafety, ModeNewRefusesAnExistingFileAndCreatesAMissingOne) {
  const fs::path dir = test::scratch_dir("outsafe", "new");
  const fs::path existing = write_file(dir / "old.nmea", "precious\n");
  const Result refused = run(kFast, {"--output", "file:" + existing.string() + "?mode=new"});
  EXPECT_EQ(refused.status, 2);
  EXPECT_TRUE(contains(refused.err, existing.string() + " already exists")) << refused.err;
  EXPECT_EQ(read_file(existing), "precious\n");

  const fs::path fresh = dir / "fresh.nmea";
  const Result made = run(kFast, {"--output", "file:" + fresh.string() + "?mode=new", "--output", "stdout"});
  ASSERT_EQ(made.status, 0) << made.err;
  EXPECT_FALSE(made.out.empty());
  EXPECT_EQ(read_file(fresh), made.out);
}

TEST(OutputSafety, FileOutputFollowsASymlinkToItsTarget) {
  // Documented (hardware.md): file: and --tee write through a symlink, as `>` in a shell does.
  const fs::path dir = test::scratch_dir("outsafe", "symlink");
  const fs::path target = write_file(dir / "target.nmea", "old\n");
  fs::create_symlink(target, dir / "link.nmea");
  const Result r = run(kFast, {"--output", "file:" + (dir / "link.nmea").string(), "--output", "stdout"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir / "link.nmea"));
  EXPECT_EQ(read_file(target), r.out);
}

}  // namespace output_safety_test
}  // namespace
}  // namespace gpsemu
