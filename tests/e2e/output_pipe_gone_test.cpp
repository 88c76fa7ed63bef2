// End to end: stdout into a real pipe whose reader exits (`| head`). The summary counts only what
// the kernel took (a partial or failed write is not an epoch written), and when every output is
// gone for good (EPIPE) gpsemu stops with a clear message and exit status 1, in --fast and in
// real time; with another output still there it runs on.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <regex>
#include <string>

#include <fmt/format.h>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace output_pipe_gone_test {

using namespace std::chrono;

/// gpsemu `args` piped into `reader`, run by bash with pipefail: the status is gpsemu's.
test::Result run_piped(const std::string& args, const std::string& reader, seconds timeout) {
  const std::string command = fmt::format("set -o pipefail; '{}' {} | {} > /dev/null", GPSEMU_BINARY, args, reader);
  return test::run({"/bin/bash", "-c", command}, timeout);
}

struct Summary {
  std::uint64_t epochs = 0, bytes = 0, failed = 0;
};

std::optional<Summary> stdout_summary(const std::string& err) {
  std::smatch m;
  if (!std::regex_search(err, m, std::regex(R"(stdout: ([0-9]+) epochs written \(([0-9]+) bytes\), [0-9]+ dropped, ([0-9]+) failed)"))) {
    return std::nullopt;
  }
  return Summary{std::stoull(m[1].str()), std::stoull(m[2].str()), std::stoull(m[3].str())};
}

TEST(OutputPipeGone, FastIntoHeadCountsOnlyWhatTheKernelTookAndExitsOne) {
  const auto r = run_piped("--fast --start-time 2024-05-01T12:00:00Z --duration 10000 --output stdout",
                           "head -c 262144", seconds(60));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("every output is gone"), std::string::npos) << r.err;
  const auto s = stdout_summary(r.err);
  ASSERT_TRUE(s) << r.err;
  // head read 256 KiB (and maybe a block more); the pipe held at most its buffer: the epochs
  // counted are those, not the 100 000 the run would have made.
  EXPECT_GE(s->bytes, 262144u) << r.err;
  EXPECT_LE(s->bytes, 262144u + 1024u * 1024u) << r.err;
  ASSERT_GT(s->epochs, 0u);
  EXPECT_LE(s->epochs * 400, s->bytes) << r.err;           // every epoch counted was taken whole
  // and no more than were taken: at most the widest epoch the start-up line states each.
  std::smatch widest;
  ASSERT_TRUE(std::regex_search(r.err, widest, std::regex(R"(([0-9]+) bytes an epoch at most)"))) << r.err;
  EXPECT_GT((s->epochs + 1) * std::stoull(widest[1]), s->bytes) << r.err;
  EXPECT_GT(s->failed, 0u) << r.err;
  // The warnings are rate-limited: a handful of lines in all.
  EXPECT_LT(std::count(r.err.begin(), r.err.end(), '\n'), 20) << r.err;
}

TEST(OutputPipeGone, RealTimeIntoHeadStopsAtOnceWithExitOne) {
  const auto begin = steady_clock::now();
  const auto r = run_piped("--rate 10 --duration 60 --output stdout", "head -1", seconds(30));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_LT(steady_clock::now() - begin, seconds(10)) << "it ran on after the reader left";
  EXPECT_NE(r.err.find("every output is gone"), std::string::npos) << r.err;
  const auto s = stdout_summary(r.err);
  ASSERT_TRUE(s) << r.err;
  EXPECT_GE(s->epochs, 1u) << r.err;
  EXPECT_LE(s->epochs, 3u) << r.err;
}

TEST(OutputPipeGone, AnotherOutputKeepsTheRunGoing) {
  const auto file = test::scratch_dir("pipe_gone", "file") / "out.nmea";
  const auto r = run_piped(fmt::format("--rate 10 --duration 2 --output stdout --output file:{}", file.string()),
                           "head -1", seconds(30));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("every output is gone"), std::string::npos) << r.err;
  // Every epoch reaches the file: written, or (a loaded machine, real time) skipped as late and
  // counted; the pipe's end loses none of them.
  std::smatch written, skipped;
  ASSERT_TRUE(std::regex_search(r.err, written, std::regex("file " + file.string() + ": ([0-9]+) epochs written"))) << r.err;
  const int late = std::regex_search(r.err, skipped, std::regex("([0-9]+) late epochs skipped")) ? std::stoi(skipped[1]) : 0;
  EXPECT_EQ(std::stoi(written[1]) + late, 20) << r.err;
  EXPECT_LE(late, 2) << r.err;
}

}  // namespace output_pipe_gone_test
}  // namespace
}  // namespace gpsemu
