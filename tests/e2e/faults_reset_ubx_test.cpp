// A reset fault against a u-blox client on a pty (an M8N in its factory state, NMEA at 5 Hz): the client
// turns NAV-PVT on (CFG-MSG, ACKed) and reads it; the receiver reboots (silent), comes back in
// its stored state (NMEA only: the client's NAV-PVT is gone) and cold (no fix); the client
// replays its configuration, which is ACKed and takes effect, and the fix returns after the TTFF.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/pty_client.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_reset_ubx_test {

namespace fs = std::filesystem;
using namespace std::chrono;

struct Seen {
  int pvt = 0, acks = 0, nmea = 0;
  int last_fix_type = -1;
};

Seen scan(const std::string& bytes) {
  Seen s;
  ubx::FrameReader reader;
  for (const ubx::ClientMessage& m : reader.feed(bytes)) {
    if (const auto* f = std::get_if<ubx::Frame>(&m)) {
      if (f->id == ubx::msg::nav_pvt) {
        ++s.pvt;
        s.last_fix_type = ubx::get_u1(f->payload, 20);
      }
      s.acks += f->id == ubx::msg::ack_ack;
    } else {
      ++s.nmea;
    }
  }
  return s;
}

TEST(FaultsResetUbx, TheConfigurationIsLostAndAReplayedSequenceTakesEffect) {
  const fs::path dir = test::scratch_dir("faults", "reset_ubx");
  const fs::path link = dir / "gps";
  const fs::path scenario = test::write_file(dir / "reset.toml", "[[fault]]\nkind = \"reset\"\nat = 3\nsilent_s = 1\nttff_s = 1.5\n");
  test::Process gpsemu({GPSEMU_BINARY, "--receiver", "ublox-m8n", "--rate", "5", "--duration",
                        "9", "--output", "pty:" + link.string(), "--scenario", scenario.string(), "--log-level", "info"});
  ASSERT_TRUE(gpsemu.wait_for_stderr("on /dev/pts", seconds(20))) << gpsemu.stderr_text();
  const int fd = test::open_raw_pty_client(link);
  ASSERT_GE(fd, 0);
  const std::string configure = ubx::frame_bytes(ubx::msg::cfg_msg, std::string("\x01\x07\x01", 3));  // NAV-PVT on
  ASSERT_EQ(::write(fd, configure.data(), configure.size()), static_cast<ssize_t>(configure.size()));
  const Seen before = scan(test::read_available(fd, milliseconds(2000), milliseconds(1200)));
  EXPECT_EQ(before.acks, 1);
  EXPECT_GE(before.pvt, 3);
  EXPECT_EQ(before.last_fix_type, 3);
  // Up to the boot (at 3 s): at 5 Hz, 600 ms without a byte is the receiver booting.
  EXPECT_GE(scan(test::read_available(fd, milliseconds(600), milliseconds(4000))).pvt, 1);
  // Back: NMEA only (RAM from the layers), no fix.
  const Seen rebooted = scan(test::read_available(fd, milliseconds(2000), milliseconds(1000)));
  EXPECT_GE(rebooted.nmea, 5) << "the stored configuration's NMEA";
  EXPECT_EQ(rebooted.pvt, 0) << "the NAV-PVT the client turned on is lost";
  // The client replays its configuration: ACKed, NAV-PVT again, the fix back after the TTFF.
  ASSERT_EQ(::write(fd, configure.data(), configure.size()), static_cast<ssize_t>(configure.size()));
  const Seen replayed = scan(test::read_available(fd, milliseconds(2000), milliseconds(2500)));
  EXPECT_EQ(replayed.acks, 1);
  EXPECT_GE(replayed.pvt, 5);
  EXPECT_EQ(replayed.last_fix_type, 3) << "the fix is back 2.5 s after the reset";
  ::close(fd);
  EXPECT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(gpsemu.stderr_text(), "fault reset silent_s=1 ttff_s=1.5 at 3 s for 2.5 s starts")) << gpsemu.stderr_text();
  fs::remove_all(dir);
}

}  // namespace faults_reset_ubx_test
}  // namespace
}  // namespace gpsemu
