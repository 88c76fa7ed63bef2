// `gpsemu ctl PATH watch` against a running gpsemu (10 Hz, a pty and --control): one JSON line an
// epoch, consecutive epochs 0.1 s apart, each matching the GGA the pty carried for that epoch
// (time, quality, satellites used, latitude and longitude to the GGA's resolution); and
// `ctl status` answers HDOP, satellites in view, the error against the truth and the outputs;
// --status-every logs its line meanwhile.
#include <gtest/gtest.h>
#include <signal.h>
#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/process.hpp"
#include "tests/support/pty_client.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace ui_ctl_watch_test {

using nlohmann::json;
using std::chrono::seconds;

/// "4304.35000","N" -> 43.0725 (degrees).
double nmea_degrees(const std::string& value, const std::string& hemisphere, int degree_digits) {
  const double degrees = std::stod(value.substr(0, static_cast<std::size_t>(degree_digits)));
  const double minutes = std::stod(value.substr(static_cast<std::size_t>(degree_digits)));
  const double out = degrees + minutes / 60.0;
  return hemisphere == "S" || hemisphere == "W" ? -out : out;
}

std::vector<std::string> fields_of(const std::string& sentence) {
  std::vector<std::string> out;
  std::stringstream in(sentence.substr(0, sentence.find('*')));
  std::string f;
  while (std::getline(in, f, ',')) out.push_back(f);
  return out;
}

TEST(UiCtlWatch, OneLineAnEpochMatchingTheFixOnThePty) {
  const auto dir = test::scratch_dir("ui", "ctl-watch");
  const std::string socket = (dir / "ctl.sock").string();
  const std::string link = (dir / "gps").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "60", "--output", "pty:" + link, "--control",
                        "unix:" + socket, "--status-every", "0.5"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("control socket", seconds(20))) << gpsemu.stderr_text();
  const int pty = test::open_raw_pty_client(link);
  ASSERT_GE(pty, 0);

  test::Process watch({GPSEMU_BINARY, "ctl", socket, "watch", "--count", "10"});
  std::string nmea;
  char buffer[4096];
  int status = -1;
  const auto deadline = std::chrono::steady_clock::now() + seconds(20);
  while (status < 0 && std::chrono::steady_clock::now() < deadline) {
    pollfd p{pty, POLLIN, 0};
    if (::poll(&p, 1, 20) > 0) {
      const ssize_t n = ::read(pty, buffer, sizeof buffer);
      if (n > 0) nmea.append(buffer, static_cast<std::size_t>(n));
    }
    gpsemu.pump(std::chrono::milliseconds(0));
    status = watch.wait(std::chrono::milliseconds(0));
  }
  // The epoch after the last watched one: its GGA follows the watched ones' on the pty.
  for (int k = 0; k < 20; ++k) {
    pollfd p{pty, POLLIN, 0};
    if (::poll(&p, 1, 20) > 0) {
      const ssize_t n = ::read(pty, buffer, sizeof buffer);
      if (n > 0) nmea.append(buffer, static_cast<std::size_t>(n));
    }
  }
  ASSERT_EQ(status, 0) << watch.stderr_text();

  std::vector<json> epochs;
  std::stringstream lines(watch.stdout_text());
  for (std::string line; std::getline(lines, line);) epochs.push_back(json::parse(line));
  ASSERT_EQ(epochs.size(), 10u) << watch.stdout_text();
  for (std::size_t k = 0; k < epochs.size(); ++k) {
    const json& e = epochs[k];
    EXPECT_EQ(e["class"], "EPOCH");
    if (k > 0) {
      EXPECT_EQ(e["epoch"].get<int>(), epochs[k - 1]["epoch"].get<int>() + 1) << "one line an epoch";
      EXPECT_NEAR(e["since_s"].get<double>() - epochs[k - 1]["since_s"].get<double>(), 0.1, 1e-6);
    }
    // "2026-11-28T05:56:47.400Z" -> GGA time "055647.40"
    const std::string t = e["time"];
    const std::string hhmmss = t.substr(11, 2) + t.substr(14, 2) + t.substr(17, 2) + "." + t.substr(20, 2);
    const std::size_t at = nmea.find("GGA," + hhmmss);
    ASSERT_NE(at, std::string::npos) << "no GGA for " << t << " on the pty";
    const std::vector<std::string> f = fields_of(nmea.substr(at, nmea.find('\n', at) - at));
    ASSERT_GE(f.size(), 10u);
    EXPECT_EQ(std::stoi(f[6]), e["fix"]["quality"].get<int>()) << t;
    EXPECT_EQ(std::stoi(f[7]), e["fix"]["satellites_used"].get<int>()) << t;
    EXPECT_NEAR(nmea_degrees(f[2], f[3], 2), e["fix"]["lat_deg"].get<double>(), 2e-7) << t;
    EXPECT_NEAR(nmea_degrees(f[4], f[5], 3), e["fix"]["lon_deg"].get<double>(), 2e-7) << t;
    EXPECT_NEAR(std::stod(f[8]), e["fix"]["hdop"].get<double>(), 0.011) << t;
    EXPECT_LT(e["error"]["horizontal_m"].get<double>(), 10.0);
  }

  const test::Result answer = test::run({GPSEMU_BINARY, "ctl", socket, "status"});
  ASSERT_EQ(answer.status, 0) << answer.err;
  const json r = json::parse(answer.out)["receivers"][0];
  EXPECT_GT(r["hdop"].get<double>(), 0.0) << answer.out;
  EXPECT_GE(r["satellites_in_view"].get<int>(), r["satellites_used"].get<int>()) << answer.out;
  EXPECT_TRUE(r["error_horizontal_m"].is_number()) << answer.out;
  EXPECT_TRUE(r["error_vertical_m"].is_number()) << answer.out;
  ASSERT_EQ(r["outputs"].size(), 1u) << answer.out;
  EXPECT_NE(r["outputs"][0]["name"].get<std::string>().find(link), std::string::npos) << answer.out;
  EXPECT_EQ(r["outputs"][0]["clients"], 1) << "the test has the pty open: " << answer.out;

  ::close(pty);
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find(" 0 late epochs skipped"), std::string::npos) << gpsemu.stderr_text();
  // --status-every: the periodic line, with the fix, HDOP and the error against the truth.
  EXPECT_NE(gpsemu.stderr_text().find("status: epoch "), std::string::npos) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("satellites used, HDOP "), std::string::npos) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find(" horizontal "), std::string::npos) << gpsemu.stderr_text();
  std::filesystem::remove_all(dir);
}

TEST(UiCtlWatch, AReceiverThatDoesNotExistIsAnErrorAnswer) {
  const auto dir = test::scratch_dir("ui", "ctl-watch-bad");
  const std::string socket = (dir / "ctl.sock").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "60", "--output", "file:" + (dir / "a.nmea").string(),
                        "--control", "unix:" + socket});
  ASSERT_TRUE(gpsemu.wait_for_stderr("control socket", seconds(20))) << gpsemu.stderr_text();
  const test::Result r = test::run({GPSEMU_BINARY, "ctl", socket, "watch", "--receiver", "3"});
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.out.find(R"("class":"ERROR")"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("receiver"), std::string::npos) << r.out;
  gpsemu.signal(SIGTERM);
  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  std::filesystem::remove_all(dir);
}

}  // namespace ui_ctl_watch_test
}  // namespace
}  // namespace gpsemu
