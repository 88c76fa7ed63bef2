// A u-blox from power-on, end to end on the gpsemu binary and a real pty:
// - `--receiver ublox-f9p` alone is the factory state: NMEA at 1 Hz and UBX answered (MON-VER) on
//   the same port; `--receiver generic` alone stays an NMEA receiver that answers nothing;
// - the pty is UART1 (docs/ublox.md "Ports"): the empty CFG-PRT poll answers port 1, turning NMEA
//   off on USB changes nothing, turning it off on UART1 stops it;
// - --receiver-state keeps BBR and flash across runs: a first run's client writes a 200 ms rate,
//   NAV-PVT on and NMEA off to BBR and flash; the file holds them; a second run with the same file
//   writes NAV-PVT every 200 ms and no NMEA from its start, with no client writing anything, and
//   CFG-VALGET reads the values back from BBR and RAM; in the first run a CFG-RST hardware reset
//   already brings them into use, and the summary counts the reset; receivers of a fleet need a
//   state file each ({i}).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace ubx_state_test {

using namespace std::chrono;
using ubx::msg::cfg_valget;
using ubx::msg::cfg_valset;

/// What the client read in a while: UBX frames and NMEA sentences.
struct Heard {
  std::vector<ubx::Frame> frames;
  std::vector<std::string> sentences;  ///< their types: "GGA", "RMC", ...
  [[nodiscard]] std::size_t count(ubx::MessageId id) const {
    std::size_t n = 0;
    for (const auto& f : frames) n += f.id == id ? 1 : 0;
    return n;
  }
};

Heard hear(int fd, milliseconds how_long) {
  ubx::FrameReader reader;
  Heard heard;
  (void)test::read_with_deadline(fd, {how_long}, [&](std::string_view bytes) {
    for (auto& m : reader.feed(bytes)) {
      if (auto* f = std::get_if<ubx::Frame>(&m)) {
        heard.frames.push_back(std::move(*f));
      } else {
        heard.sentences.push_back(std::get<nmea::Sentence>(m).type);
      }
    }
    return false;
  });
  return heard;
}

void send(int fd, ubx::MessageId id, const std::string& payload) {
  const std::string bytes = ubx::frame_bytes(id, payload);
  ASSERT_EQ(::write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
}

bool acked(const Heard& h, ubx::MessageId id) {
  for (const auto& f : h.frames) {
    if (f == ubx::test::ack_of(id)) return true;
  }
  return false;
}

test::Process start(const std::filesystem::path& link, std::vector<std::string> extra) {
  std::vector<std::string> argv = {GPSEMU_BINARY, "--rate", "1", "--noise", "none", "--output", "pty:" + link.string(),
                                   "--duration", "20", "--log-level", "info"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return test::Process(argv);
}

TEST(UbxState, AModelAloneIsItsFactoryStateAndGenericAloneStaysNmea) {
  const auto dir = test::scratch_dir("ubx_state", "factory");
  test::Process f9p = start(dir / "f9p", {"--receiver", "ublox-f9p"});
  test::Process generic = start(dir / "generic", {"--receiver", "generic"});
  ASSERT_TRUE(f9p.wait_for_stderr("NMEA+UBX on", seconds(20))) << f9p.stderr_text();
  ASSERT_TRUE(generic.wait_for_stderr("NMEA on", seconds(20))) << generic.stderr_text();
  const int f9p_fd = test::open_raw(dir / "f9p");
  const int generic_fd = test::open_raw(dir / "generic");
  send(f9p_fd, ubx::msg::mon_ver, {});
  send(generic_fd, ubx::msg::mon_ver, {});
  const Heard from_f9p = hear(f9p_fd, 2200ms);
  const Heard from_generic = hear(generic_fd, 100ms);
  EXPECT_EQ(from_f9p.count(ubx::msg::mon_ver), 1u) << "UBX answered on the NMEA port";
  EXPECT_EQ(from_f9p.count(ubx::msg::nav_pvt), 0u) << "no UBX output from the factory";
  for (const char* type : {"GGA", "RMC", "GSA", "GSV", "VTG", "GLL"}) {
    EXPECT_GE(std::count(from_f9p.sentences.begin(), from_f9p.sentences.end(), type), 2) << type;
  }
  EXPECT_TRUE(from_generic.frames.empty()) << "generic without --protocol answers nothing";
  EXPECT_FALSE(from_generic.sentences.empty());
  ::close(f9p_fd);
  ::close(generic_fd);
}

TEST(UbxState, ThePtyIsUart1AndStoredLayersSurviveARestartThroughReceiverState) {
  const auto dir = test::scratch_dir("ubx_state", "layers");
  const auto state = dir / "f9p.state";
  {
    test::Process gpsemu = start(dir / "gps", {"--receiver", "ublox-f9p", "--receiver-state", state.string()});
    ASSERT_TRUE(gpsemu.wait_for_stderr("NMEA+UBX on", seconds(20))) << gpsemu.stderr_text();
    const int fd = test::open_raw(dir / "gps");
    // The pty is UART1.
    send(fd, ubx::msg::cfg_prt, {});
    send(fd, cfg_valset, ubx::test::valset({{0x10780002, 0}}));  // CFG-USBOUTPROT-NMEA off
    Heard h = hear(fd, 1300ms);
    ASSERT_EQ(h.count(ubx::msg::cfg_prt), 1u);
    for (const auto& f : h.frames) {
      if (f.id == ubx::msg::cfg_prt) {
        EXPECT_EQ(ubx::get_u1(f.payload, 0), 1) << "port 1: UART1";
      }
    }
    EXPECT_TRUE(acked(h, cfg_valset));
    EXPECT_GE(std::count(h.sentences.begin(), h.sentences.end(), "GGA"), 1) << "USB settings do not touch the pty";
    send(fd, cfg_valset, ubx::test::valset({{ubx::key::uart1outprot_nmea, 0}}));
    (void)hear(fd, 100ms);
    h = hear(fd, 1200ms);
    EXPECT_TRUE(h.sentences.empty()) << "UART1 NMEA off: none on the pty";
    // Stored (BBR and flash), not in use: RAM keeps 1 Hz, NAV-PVT off.
    send(fd, cfg_valset,
         ubx::test::valset({{ubx::key::rate_meas, 200}, {0x20910007, 1}}, ubx::layer_bit_bbr | ubx::layer_bit_flash));
    h = hear(fd, 700ms);
    EXPECT_TRUE(acked(h, cfg_valset));
    EXPECT_EQ(h.count(ubx::msg::nav_pvt), 0u);
    // A power cycle reloads RAM from the layers: NAV-PVT every 200 ms at once; the summary counts it.
    send(fd, ubx::msg::cfg_rst, std::string("\x00\x00\x00\x00", 4));
    h = hear(fd, 700ms);
    EXPECT_GE(h.count(ubx::msg::nav_pvt), 2u);
    ::close(fd);
    gpsemu.signal(SIGTERM);
    EXPECT_EQ(gpsemu.wait(seconds(10)), 0) << gpsemu.stderr_text();
    EXPECT_NE(gpsemu.stderr_text().find("1 resets reloaded RAM from the layers"), std::string::npos)
        << gpsemu.stderr_text();
  }
  const std::string saved = test::read_file(state);
  EXPECT_NE(saved.find("bbr key 30210001 c8"), std::string::npos) << saved;
  EXPECT_NE(saved.find("flash key 20910007 1"), std::string::npos) << saved;
  // The next run: NAV-PVT every 200 ms from the start (NMEA stays on: that was RAM only).
  test::Process gpsemu = start(dir / "gps", {"--receiver", "ublox-f9p", "--receiver-state", state.string()});
  ASSERT_TRUE(gpsemu.wait_for_stderr("NMEA+UBX on", seconds(20))) << gpsemu.stderr_text();
  const int fd = test::open_raw(dir / "gps");
  const Heard h = hear(fd, 1500ms);
  std::vector<std::uint32_t> itow;
  for (const auto& f : h.frames) {
    if (f.id == ubx::msg::nav_pvt) itow.push_back(ubx::get_u4(f.payload, 0));
  }
  ASSERT_GE(itow.size(), 4u) << gpsemu.stderr_text();
  // Modulo the GPS week: a run at its end (Saturday 23:59:42 UTC) goes from 604 799 800 ms to 0.
  constexpr auto kWeekMs = static_cast<std::uint32_t>(std::chrono::milliseconds(std::chrono::weeks{1}).count());
  for (std::size_t k = 1; k < itow.size(); ++k) EXPECT_EQ((itow[k] + kWeekMs - itow[k - 1]) % kWeekMs, 200u);
  EXPECT_FALSE(h.sentences.empty());
  send(fd, cfg_valget, ubx::test::valget({ubx::key::rate_meas}, ubx::layer_bbr));
  const Heard answer = hear(fd, 400ms);
  bool read_back = false;
  for (const auto& f : answer.frames) {
    if (f.id == cfg_valget) read_back = ubx::get_u2(f.payload, 8) == 200;
  }
  EXPECT_TRUE(read_back) << "VALGET BBR reads the stored 200 ms";
  ::close(fd);
}

TEST(UbxState, TheStateFileIsNeverWrittenThroughALinkPlantedBesideIt) {
  // As root, a link at PATH.new (the old temporary's name) made gpsemu overwrite the link's target.
  const auto dir = test::scratch_dir("ubx_state", "planted-link");
  const auto state = dir / "f9p.state";
  const auto victim = test::write_file(dir / "victim", "precious\n");
  std::filesystem::create_symlink(victim, dir / "f9p.state.new");
  {
    test::Process gpsemu = start(dir / "gps", {"--receiver", "ublox-f9p", "--receiver-state", state.string()});
    ASSERT_TRUE(gpsemu.wait_for_stderr("NMEA+UBX on", seconds(20))) << gpsemu.stderr_text();
    const int fd = test::open_raw(dir / "gps");
    send(fd, cfg_valset, ubx::test::valset({{ubx::key::rate_meas, 200}}, ubx::layer_bit_bbr));
    EXPECT_TRUE(acked(hear(fd, 700ms), cfg_valset));
    ::close(fd);
    gpsemu.signal(SIGTERM);
    EXPECT_EQ(gpsemu.wait(seconds(10)), 0) << gpsemu.stderr_text();
  }
  EXPECT_EQ(test::read_file(victim), "precious\n") << "the link's target was overwritten";
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "f9p.state.new")) << "the planted link is left alone";
  EXPECT_FALSE(std::filesystem::is_symlink(state));
  EXPECT_NE(test::read_file(state).find("bbr key 30210001 c8"), std::string::npos) << test::read_file(state);
  // No temporary left behind.
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) files += entry.path().filename().string().starts_with(".") ? 1 : 0;
  EXPECT_EQ(files, 0u);
  std::filesystem::remove_all(dir);
}

TEST(UbxState, ABadReceiverStateFileStopsTheStartWithItsLine) {
  const auto dir = test::scratch_dir("ubx_state", "bad");
  const auto state = test::write_file(dir / "bad.state", "gpsemu u-blox receiver state 1\nmodel ublox-f9p\nbbr key zz 1\n");
  const auto r = test::run({GPSEMU_BINARY, "--receiver", "ublox-f9p", "--receiver-state", state.string(), "--fast",
                            "--duration", "1", "--output", "file:" + (dir / "out").string()});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("line 3"), std::string::npos) << r.err;
}

TEST(UbxState, ReceiversOfAFleetCannotShareOneStateFile) {
  const auto dir = test::scratch_dir("ubx_state", "fleet");
  const auto shared = test::run({GPSEMU_BINARY, "--receivers", "2", "--receiver", "ublox-f9p", "--receiver-state",
                                 (dir / "s.state").string(), "--fast", "--duration", "1", "--output",
                                 "file:" + (dir / "out{i}").string()});
  EXPECT_EQ(shared.status, 2) << shared.err;
  EXPECT_NE(shared.err.find("receiver-state"), std::string::npos) << shared.err;
  const auto own = test::run({GPSEMU_BINARY, "--receivers", "2", "--receiver", "ublox-f9p", "--receiver-state",
                              (dir / "s{i}.state").string(), "--fast", "--duration", "1", "--output",
                              "file:" + (dir / "out{i}").string()});
  EXPECT_EQ(own.status, 0) << own.err;
}

}  // namespace ubx_state_test
}  // namespace
}  // namespace gpsemu
