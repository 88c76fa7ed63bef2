// End to end (issue 18, memory bounds): the real gpsemu binary given hostile sizes. A config file
// over 1 MiB is refused before it is parsed; a huge value is not echoed back whole (quoted values
// are cut to 80 characters and "..."); a replayed log whose one repeated time makes an epoch of
// hundreds of thousands of sentences has that epoch skipped and counted, the others sent.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "nmea/sentences.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {

using namespace std::chrono;

struct Result {
  int rc = -1;
  std::string out, err;
};

Result run(std::vector<std::string> args) {
  args.insert(args.begin(), GPSEMU_BINARY);
  test::Process p(args);
  Result r;
  r.rc = p.wait(seconds(120));
  r.out = p.stdout_text();
  r.err = p.stderr_text();
  return r;
}

std::string gga(const std::string& time) {
  const std::string body = "GPGGA," + time + ",4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,";
  return fmt::format("${}*{:02X}\r\n", body, nmea::checksum(body));
}

TEST(MemoryBounds, AConfigFileOverOneMebibyteIsRefusedInOneShortLine) {
  const auto dir = test::scratch_dir("memory", "config_size");
  const auto big = test::write_file(dir / "big.toml", "# padding\n" + std::string(2 * 1024 * 1024, '#') + "\nrate = 5\n");
  const Result r = run({"--config", big.string(), "--fast", "--duration", "1"});
  EXPECT_EQ(r.rc, 2);
  EXPECT_TRUE(std::regex_match(r.err, std::regex("gpsemu: config file .*big.toml: larger than 1 MiB \\([0-9]+ bytes\\); a "
                                                 "config file may have at most 1048576 bytes\n")))
      << r.err;
  // Just under the limit is a config file like any other.
  const auto ok = test::write_file(dir / "ok.toml", std::string(1024 * 1024 - 100, '#') + "\nrate = 5\n");
  const Result fine = run({"--config", ok.string(), "--fast", "--duration", "1", "--output", "stdout", "--log-level", "warn"});
  EXPECT_EQ(fine.rc, 0) << fine.err;
}

TEST(MemoryBounds, AHugeValueIsCutTo80CharactersInTheMessage) {
  const auto dir = test::scratch_dir("memory", "value");
  const auto file = test::write_file(dir / "value.toml", "seed = \"" + std::string(900000, 'y') + "\"\n");
  const Result r = run({"--config", file.string(), "--fast", "--duration", "1"});
  EXPECT_EQ(r.rc, 2);
  EXPECT_TRUE(std::regex_match(r.err, std::regex("gpsemu: config file .*value.toml:1: key 'seed': seed expects a whole "
                                                 "number >= 0, got 'y{80}\\.\\.\\.'\n")))
      << r.err.substr(0, 400);
  const Result flag = run({"--noise", std::string(100000, 'p'), "--fast", "--duration", "1"});
  EXPECT_EQ(flag.rc, 2);
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
  ASSERT_EQ(r.rc, 0) << r.err;
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
  EXPECT_EQ(none.rc, 2);
  EXPECT_TRUE(std::regex_match(none.err, std::regex("gpsemu: NMEA log '.*only.nmea' has no epoch to send: 1 oversized "
                                                    "epochs \\(2000 sentences\\) skipped; an epoch may have at most 1000 "
                                                    "sentences and 131072 bytes\n")))
      << none.err;
}

}  // namespace
}  // namespace gpsemu
