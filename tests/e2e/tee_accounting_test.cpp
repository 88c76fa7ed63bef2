// End to end: the --tee copy's summary line counts an epoch as written only once the kernel took
// its bytes. A tee on /dev/full (every write fails with ENOSPC) reports every epoch failed and
// none written, in --fast (buffered, written out at the end) and in real time (each epoch at
// once), for the emulator and for replay, while the other output is written as usual; a tee
// that works reports exactly the bytes its file holds.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include <fmt/format.h>

#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace tee_accounting_test {

using namespace std::chrono;

struct TeeLine {
  std::uint64_t epochs = 0, bytes = 0, dropped = 0, failed = 0;
};

std::optional<TeeLine> tee_summary(const std::string& err, const std::string& path) {
  std::smatch m;
  const std::regex line("tee " + path + R"(: ([0-9]+) epochs written \(([0-9]+) bytes\), ([0-9]+) dropped, ([0-9]+) failed)");
  if (!std::regex_search(err, m, line)) return std::nullopt;
  return TeeLine{std::stoull(m[1].str()), std::stoull(m[2].str()), std::stoull(m[3].str()), std::stoull(m[4].str())};
}

test::Result gpsemu(std::vector<std::string> args) {
  args.insert(args.begin(), GPSEMU_BINARY);
  return test::run(args, seconds(60));
}

TEST(TeeAccounting, ATeeOnAFullDeviceCountsEveryEpochFailedInFastAndRealTime) {
  const auto dir = test::scratch_dir("tee_accounting", "full");
  const auto out = dir / "out.nmea";
  for (const bool fast : {true, false}) {
    std::vector<std::string> args{"--start-time", "2024-05-01T12:00:00Z", "--output", "file:" + out.string(), "--tee",
                                  "/dev/full"};
    if (fast) {
      args.insert(args.end(), {"--fast", "--duration", "50"});
    } else {
      args.insert(args.end(), {"--rate", "10", "--duration", "1"});
    }
    const auto r = gpsemu(args);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto tee = tee_summary(r.err, "/dev/full");
    ASSERT_TRUE(tee) << r.err;
    // Every epoch of the run is emitted, or skipped as late in real time when the machine was too
    // busy to make its deadline (counted in the summary): what was emitted is what is accounted.
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.err, m, std::regex(R"((\d+) epochs emitted \(\d+ without fix\), (\d+) late epochs skipped)")))
        << r.err;
    const std::uint64_t epochs = std::stoull(m[1].str());
    EXPECT_EQ(epochs + std::stoull(m[2].str()), fast ? 50u : 10u) << r.err;
    if (fast) {
      EXPECT_EQ(epochs, 50u) << "--fast skips nothing\n" << r.err;
    }
    EXPECT_EQ(tee->epochs, 0u) << "fast=" << fast << "\n" << r.err;
    EXPECT_EQ(tee->bytes, 0u) << r.err;
    EXPECT_EQ(tee->failed, epochs) << "fast=" << fast << "\n" << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(fmt::format("file {}: {} epochs written", out.string(), epochs)), std::string::npos) << r.err;
  }
}

TEST(TeeAccounting, AReplayTeeOnAFullDeviceCountsEveryEpochFailed) {
  const auto dir = test::scratch_dir("tee_accounting", "replay");
  const auto log = dir / "in.nmea";
  ASSERT_EQ(gpsemu({"--fast", "--start-time", "2024-05-01T12:00:00Z", "--duration", "8", "--output",
                    "file:" + log.string()}).status, 0);
  const auto r = gpsemu({"replay", log.string(), "--speed", "20", "--output", "file:" + (dir / "out.nmea").string(),
                         "--tee", "/dev/full"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto tee = tee_summary(r.err, "/dev/full");
  ASSERT_TRUE(tee) << r.err;
  EXPECT_EQ(tee->epochs, 0u) << r.err;
  EXPECT_EQ(tee->failed, 8u) << r.err;
}

TEST(TeeAccounting, AWorkingTeeCountsExactlyTheBytesItsFileHolds) {
  const auto dir = test::scratch_dir("tee_accounting", "ok");
  const auto tee_path = dir / "session.tee";
  const auto r = gpsemu({"--fast", "--start-time", "2024-05-01T12:00:00Z", "--duration", "3000", "--output",
                         "file:" + (dir / "out.nmea").string(), "--tee", tee_path.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto tee = tee_summary(r.err, tee_path.string());
  ASSERT_TRUE(tee) << r.err;
  EXPECT_EQ(tee->epochs, 3000u);
  EXPECT_EQ(tee->failed, 0u);
  EXPECT_EQ(tee->bytes, std::filesystem::file_size(tee_path)) << "the # sent lines included";
}

}  // namespace tee_accounting_test
}  // namespace
}  // namespace gpsemu
