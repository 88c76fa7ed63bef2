// End to end (issue 18, memory bounds): the real gpsemu binary given hostile sizes. A config file
// over 1 MiB is refused before it is parsed; a huge value is not echoed back whole (quoted values
// are cut to 80 characters and "..."); a replayed log whose one repeated time makes an epoch of
// hundreds of thousands of sentences has that epoch skipped and counted, the others sent.
// `gpsemu replay` streams its log: replaying a 150 MB log peaks under 64 MB of RSS (measured by
// wait4()'s ru_maxrss of the real binary; 192 MB under AddressSanitizer) and sends every epoch; a
// FIFO is streamed too (a log bigger than the look-ahead window comes out whole), and --loop on one
// is refused.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "nmea/sentences.hpp"
#include "tests/support/asan.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace memory_bounds_test {

using namespace std::chrono;

using test::Result;

/// gpsemu ARGS, run to completion.
Result run(const std::vector<std::string>& args) { return test::run({GPSEMU_BINARY}, args, seconds(120)); }

/// Runs gpsemu with `args`, standard output to /dev/null and standard error to `err_path`; the
/// exit status and the peak resident set size (kB) of the process.
std::pair<int, long> run_measured(std::vector<std::string> args, const std::filesystem::path& err_path) {
  args.insert(args.begin(), GPSEMU_BINARY);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return {-1, 0};
  int status = 0;
  rusage usage{};
  if (::wait4(pid, &status, 0, &usage) != pid) return {-1, 0};
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, usage.ru_maxrss};
}

/// Writes `bytes` into the FIFO `path` from a thread (opening blocks until gpsemu opens it).
std::thread feed_fifo(const std::filesystem::path& path, std::string bytes) {
  return std::thread([path, bytes = std::move(bytes)] {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return;
    for (std::size_t done = 0; done < bytes.size();) {
      const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n <= 0) break;  // the reader left (SIGPIPE is ignored)
      done += static_cast<std::size_t>(n);
    }
    ::close(fd);
  });
}

std::string gga(const std::string& time) {
  const std::string body = "GPGGA," + time + ",4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,";
  return fmt::format("${}*{:02X}\r\n", body, nmea::checksum(body));
}

TEST(MemoryBounds, AConfigFileOverOneMebibyteIsRefusedInOneShortLine) {
  const auto dir = test::scratch_dir("memory", "config_size");
  const auto big = test::write_file(dir / "big.toml", "# padding\n" + std::string(2 * 1024 * 1024, '#') + "\nrate = 5\n");
  const Result r = run({"--config", big.string(), "--fast", "--duration", "1"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(std::regex_match(r.err, std::regex("gpsemu: config file .*big.toml: larger than 1 MiB \\([0-9]+ bytes\\); a "
                                                 "config file may have at most 1048576 bytes\n")))
      << r.err;
  // Just under the limit is a config file like any other.
  const auto ok = test::write_file(dir / "ok.toml", std::string(1024 * 1024 - 100, '#') + "\nrate = 5\n");
  const Result fine = run({"--config", ok.string(), "--fast", "--duration", "1", "--output", "stdout", "--log-level", "warn"});
  EXPECT_EQ(fine.status, 0) << fine.err;
}

TEST(MemoryBounds, KeysOfThousandsOfPartsAndDeepValuesAreRefusedBeforeParsing) {
  // [a.a.a...] of 50 000 parts crashed gpsemu (SIGSEGV, no message), as a --config and a --scenario.
  const auto dir = test::scratch_dir("memory", "key_parts");
  std::string parts = "a";
  for (int k = 1; k < 50000; ++k) parts += ".a";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[" + parts + "]\nx = 1\n", "a key of more than 16 dotted parts"},
      {"[[fault]]\n" + parts + " = 1\n", "a key of more than 16 dotted parts"},
      {"x = " + std::string(50000, '[') + std::string(50000, ']') + "\n", "values nested deeper than 16 levels"},
      {"x = " + std::string(20000, '{') + "\n", "values nested deeper than 16 levels"}};
  for (const auto& [text, says] : cases) {
    const auto file = test::write_file(dir / "deep.toml", text);
    for (const std::string flag : {"--config", "--scenario"}) {
      const Result r = run({flag, file.string(), "--fast", "--duration", "1"});
      EXPECT_EQ(r.status, 2) << flag << " " << r.err.substr(0, 300);
      EXPECT_NE(r.err.find(says), std::string::npos) << flag << " " << r.err.substr(0, 300);
      EXPECT_NE(r.err.find("deep.toml:"), std::string::npos) << r.err.substr(0, 300);
      EXPECT_LT(r.err.size(), 300u) << r.err.substr(0, 300);
    }
  }
  // Dots in values, comments and strings are not key parts.
  const auto fine = test::write_file(dir / "fine.toml", "# a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q.r.s.t\nseed = 1\n"
                                                        "origin = \"1.2.3.4.5.6.7.8.9.10.11.12.13.14.15.16.17.18\"\n");
  const Result ok = run({"--config", fine.string(), "--fast", "--duration", "1", "--output", "stdout", "--log-level", "warn"});
  EXPECT_NE(ok.err.find("origin"), std::string::npos) << "the origin's own check, not the shape's: " << ok.err;
  EXPECT_EQ(ok.err.find("dotted parts"), std::string::npos) << ok.err;
}

TEST(MemoryBounds, AHugeValueIsCutTo80CharactersInTheMessage) {
  const auto dir = test::scratch_dir("memory", "value");
  const auto file = test::write_file(dir / "value.toml", "seed = \"" + std::string(900000, 'y') + "\"\n");
  const Result r = run({"--config", file.string(), "--fast", "--duration", "1"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(std::regex_match(r.err, std::regex("gpsemu: config file .*value.toml:1: key 'seed': seed expects a whole "
                                                 "number >= 0, got 'y{80}\\.\\.\\.'\n")))
      << r.err.substr(0, 400);
  const Result flag = run({"--noise", std::string(100000, 'p'), "--fast", "--duration", "1"});
  EXPECT_EQ(flag.status, 2);
  EXPECT_LT(flag.err.size(), 300u) << flag.err.substr(0, 400);
  EXPECT_NE(flag.err.find("'" + std::string(80, 'p') + "...'"), std::string::npos) << flag.err.substr(0, 400);
}

TEST(MemoryBounds, AnEpochOfOneRepeatedTimeWithHundredsOfThousandsOfSentencesIsSkippedAndCounted) {
  const auto dir = test::scratch_dir("memory", "epoch");
  const auto log = dir / "repeated.nmea";
  {
    std::ofstream out(log, std::ios::binary);
    for (const char* t : {"120000.00", "120001.00", "120002.00"}) out << gga(t);
    const std::string repeated = gga("120003.00");
    for (int i = 0; i < 300000; ++i) out << repeated;
    for (const char* t : {"120004.00", "120005.00"}) out << gga(t);
  }
  const Result r = run({"replay", log.string(), "--fast", "--output", "stdout"});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* t : {"120000.00", "120001.00", "120002.00", "120004.00", "120005.00"}) {
    EXPECT_NE(r.out.find(gga(t)), std::string::npos) << t;
  }
  EXPECT_EQ(r.out.find("120003.00"), std::string::npos) << "the oversized epoch was sent";
  EXPECT_EQ(r.out.size(), 5 * gga("120000.00").size());
  EXPECT_NE(r.err.find("log: 5 epochs"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 oversized epochs skipped (300000 sentences)"), std::string::npos) << r.err;

  // A log that is nothing but such an epoch has nothing to send: one line, exit 2.
  const auto only = dir / "only.nmea";
  {
    std::ofstream out(only, std::ios::binary);
    const std::string repeated = gga("120003.00");
    for (int i = 0; i < 2000; ++i) out << repeated;
  }
  const Result none = run({"replay", only.string(), "--fast", "--output", "stdout"});
  EXPECT_EQ(none.status, 2);
  EXPECT_TRUE(std::regex_match(none.err, std::regex("gpsemu: NMEA log '.*only.nmea' has no epoch to send: 1 oversized "
                                                    "epochs \\(2000 sentences\\) skipped; an epoch may have at most 1000 "
                                                    "sentences and 131072 bytes\n")))
      << none.err;
}

// Under AddressSanitizer (tools/reliability) freed memory sits in a 256 MB quarantine and every
// allocation carries redzones: the child runs without the quarantine and the bound is 192 MB
// (measured 95-103 MB with GCC, 71 MB with clang); a log held whole takes gigabytes either way (2.8 GB without sanitizers).
#if defined(GPSEMU_TEST_ASAN)
constexpr long kPeakBoundKb = 192 * 1024;
#else
constexpr long kPeakBoundKb = 64 * 1024;
#endif
using test::without_asan_quarantine;

TEST(MemoryBounds, ReplayingA150MBLogPeaksUnder64MBAndSendsEveryEpoch) {
  const auto dir = test::scratch_dir("memory", "replay_rss");
  const auto log = dir / "big.nmea";
  // 262 144 epochs of the emulator's default sentences at 1 Hz: about 150 MB.
  constexpr int kEpochs = 262144;
  ASSERT_EQ(run({"--fast", "--start-time", "2024-05-01T12:00:00Z", "--duration", std::to_string(kEpochs), "--output",
                 "file:" + log.string(), "--log-level", "warn"}).status, 0);
  ASSERT_GT(std::filesystem::file_size(log), 140'000'000u);
  const auto err = dir / "replay.err";
  without_asan_quarantine();
  const auto [rc, peak_kb] = run_measured({"replay", log.string(), "--fast", "--output", "stdout"}, err);
  const std::string text = test::read_file(err);
  std::filesystem::remove(log);
  ASSERT_EQ(rc, 0) << text;
  EXPECT_NE(text.find(fmt::format("{} epochs sent", kEpochs)), std::string::npos) << text;
  EXPECT_NE(text.find(fmt::format("log: {} epochs", kEpochs)), std::string::npos) << text;
  EXPECT_LT(peak_kb, kPeakBoundKb) << "peak RSS " << peak_kb << " kB: the log is not streamed";
  std::printf("[ info ] replay --fast of a %d-epoch log: peak RSS %ld kB\n", kEpochs, peak_kb);
}

TEST(MemoryBounds, AFifoLogIsStreamedWholeAndLoopOnItIsRefused) {
  ::signal(SIGPIPE, SIG_IGN);
  const auto dir = test::scratch_dir("memory", "fifo");
  const auto file = dir / "log.nmea";
  // 4000 epochs, about 2.3 MB: more than the look-ahead window.
  ASSERT_EQ(run({"--fast", "--start-time", "2024-05-01T12:00:00Z", "--duration", "4000", "--output",
                 "file:" + file.string(), "--log-level", "warn"}).status, 0);
  const std::string bytes = test::read_file(file);
  const auto fifo = dir / "log.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer = feed_fifo(fifo, bytes);
  const Result r = run({"replay", fifo.string(), "--fast", "--output", "stdout"});
  writer.join();
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out == bytes) << "the FIFO's epochs, all of them, unchanged (" << r.out.size() << " of " << bytes.size()
                              << " bytes)";
  EXPECT_NE(r.err.find("log: 4000 epochs"), std::string::npos) << r.err;

  // A FIFO can be read only once: --loop is refused at start-up.
  writer = feed_fifo(fifo, gga("120000.00") + gga("120001.00"));
  const Result loop = run({"replay", fifo.string(), "--loop", "--duration", "5", "--fast", "--output", "stdout"});
  writer.join();
  EXPECT_EQ(loop.status, 2);
  EXPECT_TRUE(std::regex_match(loop.err, std::regex("gpsemu: --loop: NMEA log '.*log.fifo' is not a regular file: a "
                                                    "pipe can be read only once\n")))
      << loop.err;
}

}  // namespace memory_bounds_test
}  // namespace
}  // namespace gpsemu
