// Live faults over the control socket while gpsemu runs in real time at 10 Hz: `gpsemu ctl`
// starts an outage of 1 s, the NMEA shows exactly 10 epochs without a fix from the epoch after
// the request, status reports it, no epoch is late, and a bad request is an ERROR answer (exit 1).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_control_test {

using std::chrono::seconds;

TEST(FaultsControl, CtlStartsAnOutageAtTheNextEpochAt10HzWithoutLateEpochs) {
  const auto dir = test::scratch_dir("faults", "control");
  const std::string socket = (dir / "ctl.sock").string(), file = (dir / "out.nmea").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "5", "--output", "file:" + file, "--control",
                        "unix:" + socket, "--log-level", "info"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("control socket", seconds(20))) << gpsemu.stderr_text();

  const auto asked = std::chrono::steady_clock::now();
  const test::Result fault = test::run({GPSEMU_BINARY, "ctl", socket, "outage", "--duration", "1"});
  const double answer_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - asked).count();
  ASSERT_EQ(fault.status, 0) << fault.err;
  EXPECT_EQ(nlohmann::json::parse(fault.out)["class"], "FAULT") << fault.out;
  std::cout << "ctl answered in " << answer_ms << " ms (process start included)\n";

  const test::Result status = test::run({GPSEMU_BINARY, "ctl", socket, "status"});
  ASSERT_EQ(status.status, 0) << status.err;
  const auto s = nlohmann::json::parse(status.out);
  EXPECT_EQ(s["class"], "STATUS");
  EXPECT_EQ(s["receivers"].size(), 1u);

  const test::Result bad = test::run({GPSEMU_BINARY, "ctl", socket, "jam", "--db", "-3"});
  EXPECT_EQ(bad.status, 1);
  EXPECT_TRUE(test::contains(bad.out, R"("class":"ERROR")")) << bad.out;

  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(err, " 0 late epochs skipped")) << err;
  EXPECT_TRUE(test::contains(err, "fault outage at ")) << err;
  EXPECT_TRUE(test::contains(err, "for 1 s: 10 epochs")) << err;

  // The GGAs: one run of exactly 10 epochs without a fix, the others with.
  nmea::StreamReader reader;
  std::vector<bool> fixes;
  for (const auto& sentence : reader.feed(test::read_file(file))) {
    if (sentence.type != "GGA") continue;
    const auto gga = nmea::parse_gga(sentence);
    ASSERT_TRUE(gga.ok());
    fixes.push_back(gga->quality != nmea::FixQuality::none);
  }
  EXPECT_EQ(fixes.size(), 50u);
  int runs = 0, without = 0;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    without += !fixes[i];
    runs += !fixes[i] && (i == 0 || fixes[i - 1]);
  }
  EXPECT_EQ(without, 10);
  EXPECT_EQ(runs, 1);
  std::filesystem::remove_all(dir);
}

}  // namespace faults_control_test
}  // namespace
}  // namespace gpsemu
