// Serial output: serial specs, finding a USB adapter by identity in a
// port list (and re-finding it after a replug, with a fake list), and SerialOutput against a
// socat pseudo-terminal pair standing in for a UART: whole epochs at the far end, input
// discarded, a stalled line dropping whole epochs without blocking, hang-up and reopen.
#include <gtest/gtest.h>
#include <poll.h>
#include <stdlib.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/nmea_check.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"
#include "transport/output_spec.hpp"
#include "transport/serial_output.hpp"
#include "transport/serial_ports.hpp"

namespace gpsemu::transport {
namespace {
namespace serial_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

using test::epoch;

// ---------------------------------------------------------------------------------------------
// Specs

TEST(SerialSpecTest, ValidSpecsParseAndReadBack) {
  struct Case {
    std::string text;
    std::string path;
    int baud;
    std::optional<UsbSelector> usb;
  };
  const std::vector<Case> cases = {
      {"serial:/dev/ttyUSB0@115200", "/dev/ttyUSB0", 115200, std::nullopt},
      {"serial:/dev/ttyS1", "/dev/ttyS1", 0, std::nullopt},
      {"serial:/tmp/gps@4800", "/tmp/gps", 4800, std::nullopt},
      {"serial:/dev/serial/by-path/platform-soc@x:1.0", "/dev/serial/by-path/platform-soc@x:1.0", 0, std::nullopt},
      {"serial:usb:0403:6001", "", 0, UsbSelector{0x0403, 0x6001, ""}},
      {"serial:usb:0403:6001@921600", "", 921600, UsbSelector{0x0403, 0x6001, ""}},
      {"serial:usb:10c4:ea60:0001@9600", "", 9600, UsbSelector{0x10c4, 0xea60, "0001"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    const OutputSpec spec = parse_output_spec(c.text);
    EXPECT_EQ(spec.kind, OutputKind::serial);
    EXPECT_EQ(spec.path, fs::path(c.path));
    EXPECT_EQ(spec.baud_bps, c.baud);
    EXPECT_EQ(spec.usb, c.usb);
    EXPECT_EQ(to_string(spec), c.text);
  }
}

TEST(SerialSpecTest, InvalidSpecsNameTheProblem) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"serial", "needs a device"},
      {"serial:", "needs a device"},
      {"serial:/dev/ttyUSB0@1234", "baud 1234 is not supported"},
      {"serial:/dev/ttyUSB0@250000", "4800, 9600"},
      {"serial:/dev/ttyUSB0@", "needs a baud"},
      {"serial:usb:0403", "VID:PID"},
      {"serial:usb:xyz:6001", "vendor ID"},
      {"serial:usb:0403:123456", "product ID"},
      {"serial:usb:0403:6001:", "serial number"},
  };
  for (const auto& [text, expected] : cases) {
    SCOPED_TRACE(text);
    try {
      (void)parse_output_spec(text);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("'" + text + "'"), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Finding adapters

SerialPortInfo usb_port(std::string device, std::uint16_t vid, std::uint16_t pid, std::string serial) {
  SerialPortInfo p;
  p.device = std::move(device);
  p.transport = "usb";
  p.description = "FT232R USB UART";
  p.usb_vid = vid;
  p.usb_pid = pid;
  p.usb_serial = std::move(serial);
  return p;
}

SerialPortInfo native_port(std::string device) {
  SerialPortInfo p;
  p.device = std::move(device);
  p.transport = "native";
  return p;
}

TEST(UsbLookupTest, FindsTheOneAdapterByVidPidAndSerial) {
  const std::vector<SerialPortInfo> ports = {native_port("/dev/ttyS0"), usb_port("/dev/ttyUSB0", 0x0403, 0x6001, "A1"),
                                             usb_port("/dev/ttyUSB1", 0x0403, 0x6001, "B2"),
                                             usb_port("/dev/ttyACM0", 0x1546, 0x01a8, "")};
  EXPECT_EQ(lookup_usb_port(ports, {0x0403, 0x6001, "B2"}).device, "/dev/ttyUSB1");
  EXPECT_EQ(lookup_usb_port(ports, {0x1546, 0x01a8, ""}).device, "/dev/ttyACM0");
  EXPECT_EQ(find_usb_ports(ports, {0x0403, 0x6001, ""}).size(), 2u);
}

TEST(UsbLookupTest, SeveralMatchesAskForTheSerialNumber) {
  const std::vector<SerialPortInfo> ports = {usb_port("/dev/ttyUSB0", 0x0403, 0x6001, "A1"),
                                             usb_port("/dev/ttyUSB1", 0x0403, 0x6001, "B2")};
  const UsbLookup found = lookup_usb_port(ports, {0x0403, 0x6001, ""});
  EXPECT_FALSE(found.device);
  EXPECT_NE(found.problem.find("2 USB serial adapters match 0403:6001"), std::string::npos) << found.problem;
  EXPECT_NE(found.problem.find("/dev/ttyUSB1"), std::string::npos) << found.problem;
  EXPECT_NE(found.problem.find("serial:usb:0403:6001:SERIAL"), std::string::npos) << found.problem;
}

TEST(UsbLookupTest, NoMatchNamesTheSelectorAndWhatIsConnected) {
  const std::vector<SerialPortInfo> ports = {native_port("/dev/ttyS0"), usb_port("/dev/ttyUSB0", 0x10c4, 0xea60, "7")};
  const UsbLookup found = lookup_usb_port(ports, {0x0403, 0x6001, "A1"});
  EXPECT_FALSE(found.device);
  EXPECT_NE(found.problem.find("no USB serial adapter 0403:6001:A1"), std::string::npos) << found.problem;
  EXPECT_NE(found.problem.find("/dev/ttyUSB0 usb 10c4:ea60"), std::string::npos) << found.problem;
}

TEST(UsbLookupTest, SystemListerAnswers) {
  // No USB here; the list may be empty or hold board UARTs, but reading it must work.
  const auto ports = make_system_port_lister()->list_ports();
  for (const auto& p : ports) EXPECT_FALSE(p.device.empty());
}

/// A port list the test changes, as plugging and unplugging would.
class FakePortLister final : public PortLister {
 public:
  std::vector<SerialPortInfo> ports;
  int calls = 0;
  std::vector<SerialPortInfo> list_ports() override {
    ++calls;
    return ports;
  }
};

// ---------------------------------------------------------------------------------------------
// SerialOutput against a socat pty pair

class SerialOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(test::socat_path().empty()) << "socat is needed: tools/setup --with-test-deps installs it";
    std::string templ = (test::scratch_root() / "gpsemu_serial_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
  }
  void TearDown() override { fs::remove_all(dir_); }

  static SerialOptions options(int baud = 115200) {
    SerialOptions o;
    o.baud_bps = baud;
    o.max_queue_s = 0.1;
    o.rescan_interval = 20ms;
    return o;
  }

  /// Calls service() (as the runner does when the descriptor is readable) until `done` or timeout.
  template <class Done>
  static bool service_until(SerialOutput& out, Done done, std::chrono::milliseconds timeout = 5s) {
    const auto deadline = Clock::now() + timeout;
    while (!done()) {
      if (Clock::now() > deadline) return false;
      pollfd pfd{out.poll_fd(), POLLIN, 0};
      (void)::poll(&pfd, out.poll_fd() >= 0 ? 1 : 0, 10);
      out.service();
    }
    return true;
  }

  fs::path dir_;
};

TEST_F(SerialOutputTest, FarEndReadsEveryEpochWholeAndInOrder) {
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  SerialOutput out(SerialTarget{pair.a(), std::nullopt}, options());
  const int far = test::open_raw(pair.b());
  std::string expected;
  std::string received;
  for (int k = 0; k < 20; ++k) {
    const std::string e = epoch(k);
    ASSERT_EQ(out.write_epoch(e), WriteStatus::ok);
    expected += e;
    received += test::read_available(far, 2s, 5s, e.size());
  }
  ::close(far);
  EXPECT_EQ(received, expected);
  EXPECT_EQ(out.stats().epochs_written, 20u);
  EXPECT_EQ(out.stats().epochs_dropped, 0u);
  EXPECT_NE(out.describe().find("serial:" + pair.a().string() + "@115200 (/dev/pts/"), std::string::npos)
      << out.describe();
}

TEST_F(SerialOutputTest, LineIsRaw8N1WithoutFlowControlAtTheGivenBaud) {
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  SerialOutput out(SerialTarget{pair.a(), std::nullopt}, options(4800));
  termios tio{};
  ASSERT_EQ(::tcgetattr(out.poll_fd(), &tio), 0);
  EXPECT_EQ(::cfgetospeed(&tio), static_cast<speed_t>(B4800));
  EXPECT_EQ(tio.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
  EXPECT_EQ(tio.c_cflag & (PARENB | CSTOPB | CRTSCTS), 0u);
  EXPECT_NE(tio.c_cflag & CLOCAL, 0u);
  EXPECT_EQ(tio.c_iflag & (IXON | IXOFF), 0u);
  EXPECT_EQ(tio.c_lflag & (ICANON | ECHO), 0u);
  EXPECT_EQ(tio.c_oflag & OPOST, 0u);
}

TEST_F(SerialOutputTest, WhatTheFarEndWritesIsReadAndDiscarded) {
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  SerialOutput out(SerialTarget{pair.a(), std::nullopt}, options());
  const int far = test::open_raw(pair.b());
  const std::string probe(3000, '?');  // gpsd probes with strings like this
  ASSERT_EQ(::write(far, probe.data(), probe.size()), static_cast<ssize_t>(probe.size()));
  ASSERT_TRUE(service_until(out, [&] { return out.serial_stats().input_bytes_discarded >= probe.size(); }));
  EXPECT_EQ(out.serial_stats().input_bytes_discarded, probe.size());
  ASSERT_EQ(out.write_epoch(epoch(0)), WriteStatus::ok);
  EXPECT_EQ(test::read_available(far, 2s, 5s, epoch(0).size()), epoch(0));
  ::close(far);
}

TEST_F(SerialOutputTest, StalledLineDropsWholeEpochsWithoutBlockingAndNeverHalfSentences) {
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  SerialOutput out(SerialTarget{pair.a(), std::nullopt}, options());
  const int far = test::open_raw(pair.b());  // opened, never read: the line stalls
  auto slowest = Clock::duration::zero();
  int k = 0;
  for (; k < 5000 && out.stats().epochs_dropped < 20; ++k) {
    const auto start = Clock::now();
    (void)out.write_epoch(epoch(k));
    slowest = std::max(slowest, Clock::now() - start);
  }
  ASSERT_GE(out.stats().epochs_dropped, 20u) << "the line never filled up";
  EXPECT_LT(slowest, 50ms) << "a write blocked the epoch loop";
  // The reader comes back: what it gets is whole epochs only, every epoch the output accepted.
  std::string received;
  const auto deadline = Clock::now() + 10s;
  while (Clock::now() < deadline) {
    received += test::read_available(far, 200ms, 1s);
    out.service();  // finishes an epoch the kernel took only part of
    const std::string more = test::read_available(far, 200ms, 1s);
    received += more;
    if (more.empty() && !received.empty()) break;
  }
  ::close(far);
  const test::SplitResult split = test::split_sentences(received);
  EXPECT_EQ(split.invalid, 0u);
  EXPECT_EQ(split.rest, "") << "half a sentence reached the far end";
  EXPECT_EQ(split.sentences.size(), 2 * out.stats().epochs_written);
  EXPECT_EQ(out.serial_stats().device_losses, 0u);
  for (std::size_t i = 0; i + 1 < split.sentences.size(); i += 2) {
    ASSERT_EQ(test::sentence_type(split.sentences[i]), "GGA");
    ASSERT_EQ(test::sentence_type(split.sentences[i + 1]), "RMC");
    ASSERT_EQ(test::time_field(split.sentences[i]), test::time_field(split.sentences[i + 1]));
  }
  std::printf("stalled line: %d epochs offered, %llu written whole, %llu dropped, slowest write %.3f ms\n", k,
              static_cast<unsigned long long>(out.stats().epochs_written),
              static_cast<unsigned long long>(out.stats().epochs_dropped),
              std::chrono::duration<double, std::milli>(slowest).count());
}

TEST_F(SerialOutputTest, HangUpIsNoticedAndTheDeviceReopenedWhenItComesBack) {
  auto pair = std::make_unique<test::SocatPair>(dir_ / "A", dir_ / "B");
  SerialOutput out(SerialTarget{pair->a(), std::nullopt}, options());
  ASSERT_EQ(out.write_epoch(epoch(0)), WriteStatus::ok);
  pair->stop();  // unplugged
  ASSERT_TRUE(service_until(out, [&] { return !out.is_open(); })) << "hang-up not noticed";
  EXPECT_EQ(out.serial_stats().device_losses, 1u);
  EXPECT_EQ(out.write_epoch(epoch(1)), WriteStatus::error);
  EXPECT_NE(out.describe().find("lost"), std::string::npos) << out.describe();

  pair = std::make_unique<test::SocatPair>(dir_ / "A", dir_ / "B");  // plugged back
  ASSERT_TRUE(service_until(out, [&] { return out.is_open(); })) << "not reopened: " << out.describe();
  EXPECT_EQ(out.serial_stats().reopens, 1u);
  const int far = test::open_raw(pair->b());
  ASSERT_EQ(out.write_epoch(epoch(2)), WriteStatus::ok);
  EXPECT_EQ(test::read_available(far, 2s, 5s, epoch(2).size()), epoch(2));
  ::close(far);
}

TEST_F(SerialOutputTest, UsbAdapterIsFoundAgainUnderAnotherName) {
  // Two pty pairs stand in for ttyUSB0 and, after a replug, ttyUSB1; the fake port list says
  // which one the adapter 0403:6001 serial FT1 is at.
  auto lister = std::make_shared<FakePortLister>();
  auto first = std::make_unique<test::SocatPair>(dir_ / "USB0", dir_ / "far0");
  lister->ports = {usb_port((dir_ / "USB0").string(), 0x0403, 0x6001, "FT1"),
                   usb_port("/dev/nonexistent-other", 0x0403, 0x6015, "X")};
  SerialOutput out(SerialTarget{{}, UsbSelector{0x0403, 0x6001, "FT1"}}, options(), lister);
  EXPECT_NE(out.describe().find("serial:usb:0403:6001:FT1@115200"), std::string::npos) << out.describe();
  {
    const int far = test::open_raw(first->b());
    ASSERT_EQ(out.write_epoch(epoch(0)), WriteStatus::ok);
    EXPECT_EQ(test::read_available(far, 2s, 5s, epoch(0).size()), epoch(0));
    ::close(far);
  }
  lister->ports = {lister->ports[1]};  // unplugged
  first->stop();
  ASSERT_TRUE(service_until(out, [&] { return !out.is_open(); }));
  const int calls_before = lister->calls;
  ASSERT_TRUE(service_until(out, [&] { return lister->calls >= calls_before + 3; })) << "no rescans";
  EXPECT_FALSE(out.is_open());

  auto second = std::make_unique<test::SocatPair>(dir_ / "USB1", dir_ / "far1");  // back as ttyUSB1
  lister->ports.push_back(usb_port((dir_ / "USB1").string(), 0x0403, 0x6001, "FT1"));
  ASSERT_TRUE(service_until(out, [&] { return out.is_open(); })) << out.describe();
  EXPECT_EQ(out.serial_stats().reopens, 1u);
  const int far = test::open_raw(second->b());
  ASSERT_EQ(out.write_epoch(epoch(1)), WriteStatus::ok);
  EXPECT_EQ(test::read_available(far, 2s, 5s, epoch(1).size()), epoch(1));
  ::close(far);
}

TEST_F(SerialOutputTest, UsbAdapterMissingAtStartUpIsRefusedNamingIt) {
  auto lister = std::make_shared<FakePortLister>();
  lister->ports = {native_port("/dev/ttyS0")};
  try {
    SerialOutput out(SerialTarget{{}, UsbSelector{0x0403, 0x6001, ""}}, options(), lister);
    ADD_FAILURE() << "opened";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no USB serial adapter 0403:6001 is connected"), std::string::npos)
        << e.what();
  }
}

TEST_F(SerialOutputTest, StartUpErrorsNameTheDevice) {
  const auto message = [&](const fs::path& path) {
    try {
      SerialOutput out(SerialTarget{path, std::nullopt}, options());
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("opened");
  };
  const std::string missing = message("/nonexistent/ttyUSB7");
  EXPECT_NE(missing.find("/nonexistent/ttyUSB7"), std::string::npos) << missing;
  EXPECT_NE(missing.find("no such device"), std::string::npos) << missing;

  const fs::path file = dir_ / "plain.txt";
  std::ofstream(file) << "not a tty\n";
  const std::string not_tty = message(file);
  EXPECT_NE(not_tty.find("not a serial device"), std::string::npos) << not_tty;

  test::SocatPair pair(dir_ / "A", dir_ / "B");
  SerialOutput first(SerialTarget{pair.a(), std::nullopt}, options());
  const std::string busy = message(pair.a());
  EXPECT_NE(busy.find("in use"), std::string::npos) << busy;
}

TEST_F(SerialOutputTest, PseudoTerminalHasNoModemLinesForPps) {
  test::SocatPair pair(dir_ / "A", dir_ / "B");
  SerialOutput out(SerialTarget{pair.a(), std::nullopt}, options());
  try {
    out.check_modem_line(ModemLine::rts);
    ADD_FAILURE() << "a pty claimed to have RTS";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no RTS modem control line"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pseudo-terminal"), std::string::npos) << e.what();
  }
  std::string error_text;
  EXPECT_FALSE(out.set_modem_line(ModemLine::dtr, true, error_text));
  EXPECT_NE(error_text.find("DTR"), std::string::npos) << error_text;
}

}  // namespace serial_test
}  // namespace
}  // namespace gpsemu::transport
