// Serial output end to end through the binary: a reader at the far end of a socat pty pair gets
// valid, whole epochs at 10 Hz over serial:...@230400; a baud too slow for the rate is refused at
// start-up naming a baud that fits; a missing device and PPS on a pty's modem line exit 2 with a
// clear message; `gpsemu ports` lists ports (or says there are none).
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <fmt/format.h>

#include "nmea/sentences.hpp"
#include "tests/support/nmea_check.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"

namespace gpsemu {
namespace {
namespace hw_serial_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using test::seconds_of_day;

class SerialEndToEndTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(test::socat_path().empty()) << "socat is needed: tools/setup --with-test-deps installs it";
    std::string templ = (test::scratch_root() / "gpsemu_serial_e2e_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// 230400 baud: the default sentences of the default model (an M8N: GPS, GLONASS, QZSS, SBAS, each
// system its own GSV groups and GSA) take up to 1 170 bytes an epoch, more than 115200 baud carries
// at 10 Hz within the start-up check's 90% (a real M8N's sky wrote up to 905 bytes).
TEST_F(SerialEndToEndTest, FarEndOfAPtyPairGetsValidEpochsAt10HzOver230400Baud) {
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  const int far = test::open_raw(pair.b());
  test::Process gpsemu({GPSEMU_BINARY, "--output", "serial:" + pair.a().string() + "@230400", "--rate", "10",
                        "--duration", "3", "--log-level", "info"});
  std::string received;
  int status = -1;
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (status < 0 && std::chrono::steady_clock::now() < deadline) {
    received += test::read_available(far, 50ms, 50ms);
    status = gpsemu.wait(1ms);
  }
  received += test::read_available(far, 300ms, 2s);
  ::close(far);
  ASSERT_EQ(status, 0) << gpsemu.stderr_text();
  const test::SplitResult split = test::split_sentences(received);
  EXPECT_EQ(split.invalid, 0u);
  EXPECT_EQ(split.rest, "");
  std::vector<double> times;
  for (const auto& s : split.sentences) {
    if (test::sentence_type(s) == "RMC") times.push_back(seconds_of_day(test::time_field(s)));
  }
  EXPECT_EQ(times.size(), 30u) << gpsemu.stderr_text();
  for (std::size_t i = 1; i < times.size(); ++i) EXPECT_NEAR(times[i] - times[i - 1], 0.1, 1e-6) << i;
  EXPECT_NE(gpsemu.stderr_text().find("30 epochs written"), std::string::npos) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("0 dropped, 0 failed"), std::string::npos) << gpsemu.stderr_text();
}

TEST_F(SerialEndToEndTest, BaudTooSlowForTheRateIsRefusedNamingABaudThatFits) {
  const auto r = test::run({GPSEMU_BINARY, "--output", "serial:" + (dir_ / "A").string() + "@4800", "--rate", "10",
                            "--duration", "1"});
  EXPECT_EQ(r.status, 2);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.err, m, std::regex("does not fit 4800 baud.*use ([0-9]+) baud or more"))) << r.err;
  const int baud = std::stoi(m[1]);
  EXPECT_TRUE(baud == 19200 || baud == 38400 || baud == 57600 || baud == 115200 || baud == 230400) << baud;
  EXPECT_NE(r.err.find("@" + std::to_string(baud)), std::string::npos) << r.err;  // the spec that would fit
  // The same line at the baud it names starts (here: no device, so it fails later, at the open).
  const auto ok = test::run({GPSEMU_BINARY, "--output", "serial:" + (dir_ / "A").string() + "@" + std::to_string(baud),
                             "--rate", "10", "--duration", "1"});
  EXPECT_EQ(ok.status, 2);
  EXPECT_EQ(ok.err.find("does not fit"), std::string::npos) << ok.err;
  EXPECT_NE(ok.err.find("no such device"), std::string::npos) << ok.err;
}

TEST_F(SerialEndToEndTest, StartUpFailuresExit2WithOneClearMessage) {
  const auto missing = test::run({GPSEMU_BINARY, "--output", "serial:/dev/ttyUSB93@115200", "--duration", "1"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("cannot open /dev/ttyUSB93: no such device"), std::string::npos) << missing.err;

  const auto usb = test::run({GPSEMU_BINARY, "--output", "serial:usb:0403:6001:NOPE@115200", "--duration", "1"});
  EXPECT_EQ(usb.status, 2);
  EXPECT_NE(usb.err.find("no USB serial adapter 0403:6001:NOPE is connected"), std::string::npos) << usb.err;

  const auto bad_baud = test::run({GPSEMU_BINARY, "--output", "serial:/dev/ttyUSB0@14400", "--duration", "1"});
  EXPECT_EQ(bad_baud.status, 2);
  EXPECT_NE(bad_baud.err.find("baud 14400 is not supported"), std::string::npos) << bad_baud.err;
}

TEST_F(SerialEndToEndTest, PpsOnAPseudoTerminalModemLineIsRefused) {
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  const auto r = test::run({GPSEMU_BINARY, "--output", "serial:" + pair.a().string() + "@115200", "--pps", "modem:RTS",
                            "--duration", "1"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("has no RTS modem control line"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pseudo-terminal"), std::string::npos) << r.err;
}

TEST(PortsCommandTest, ListsSerialPortsOrSaysThereAreNone) {
  const auto r = test::run({GPSEMU_BINARY, "ports"});
  EXPECT_EQ(r.status, 0) << r.err;
  const bool listed = r.out.rfind("DEVICE", 0) == 0 && r.out.find("VID:PID") != std::string::npos &&
                      r.out.find("SERIAL") != std::string::npos;
  EXPECT_TRUE(listed || r.out == "no serial ports found\n") << r.out;
}

// A replay checks the serial line against the widest epoch of its look-ahead window (1024
// epochs and one 64 KiB read) at start-up; wider epochs further on are sent and counted, with one
// warning.
TEST_F(SerialEndToEndTest, AReplayCountsEpochsWiderThanTheLineBeyondItsLookAhead) {
  auto sentence = [](const std::string& body) { return fmt::format("${}*{:02X}\r\n", body, nmea::checksum(body)); };
  const auto log = dir_ / "wide_later.nmea";
  {
    std::ofstream out(log, std::ios::binary);
    for (int i = 0; i < 2200; ++i) {  // 10 Hz from 12:00:00
      const std::string t = fmt::format("12{:02}{:02}.{}0", i / 10 / 60, i / 10 % 60, i % 10);
      out << sentence("GPGGA," + t + ",4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,");
      if (i >= 2196) out << sentence("GPRMC," + t + ",A,4304.35012,N,08924.75027,W,0.000,,010524,,,A,V");
    }
  }
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  const int far = test::open_raw(pair.b());
  // 1000 epochs a second at 921600 baud: 82 bytes an epoch within the 90 % margin; a GGA is 75.
  test::Process gpsemu({GPSEMU_BINARY, "replay", log.string(), "--speed", "100", "--output",
                        "serial:" + pair.a().string() + "@921600"});
  int status = -1;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (status < 0 && std::chrono::steady_clock::now() < deadline) {
    (void)test::read_available(far, 50ms, 50ms);
    status = gpsemu.wait(1ms);
  }
  ::close(far);
  ASSERT_EQ(status, 0) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("2200 epochs sent"), std::string::npos) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("0 steps back"), std::string::npos) << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("4 epochs wider than the 82 bytes the slowest serial line carries"),
            std::string::npos)
      << gpsemu.stderr_text();
  EXPECT_NE(gpsemu.stderr_text().find("epoch at 12:03:39.600 is 144 bytes: wider than the 82 bytes"), std::string::npos)
      << gpsemu.stderr_text();
}

}  // namespace hw_serial_test
}  // namespace
}  // namespace gpsemu
