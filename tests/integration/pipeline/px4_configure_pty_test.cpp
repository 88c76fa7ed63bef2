// PX4's u-blox driver configuring a NEO-M8N through a real pseudo-terminal (issue 35: found by
// tools/driver-check, PX4-GPSDrivers' own driver over gpsemu's pty). The frames PX4 wrote
// (tests/data/px4/neo_m8n_configure.txt, recorded from its wire trace) are replayed in order
// against the receiver channel behind a PtyOutput, with the epoch loop's steps around each as the
// trace showed them: the loop's check of the pty (prepare) before the frame, the answer written,
// then the next epoch's check before the driver read the answer (PX4 waits for 32 characters
// after poll() wakes, 2.8 ms at 115200 baud), an epoch with nothing to send (a u-blox being
// configured has its messages off). PX4 waits 250 ms for each ACK and restarts its whole
// configuration without it: every frame must get its answer (ACK-ACK; ACK-NAK for the VALSET
// probe an M8 does not know; MON-VER for the poll). The check took the answer, the only thing
// written since the previous check, for bytes no client had read for a whole period and
// discarded it (8 of 54 boots restarted); and when the driver had opened the port after an
// epoch went in while nobody had it open, the next check discarded everything unread, the
// answers to the frames it wrote since (MON-VER lost: board unknown, a restart). The same driver
// configuring an M10 (tests/data/px4/max_m10s_configure.txt) gets the answers a MAX-M10S gives.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/pipeline/protocol_effects.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "emulator/ubx/bytes.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/ubx_frames.hpp"
#include "transport/pty_output.hpp"

namespace gpsemu {
namespace {
namespace px4_configure_pty_test {

using namespace std::chrono_literals;
using ubx::test::frames_in;

/// The recorded frames: one hex line each, '#' comments.
std::vector<std::string> recorded_frames(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> frames;
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find('#'));
    while (!line.empty() && line.back() == ' ') line.pop_back();
    if (line.empty()) continue;
    std::string bytes;
    for (std::size_t k = 0; k + 1 < line.size(); k += 2) {
      bytes.push_back(static_cast<char>(std::stoi(line.substr(k, 2), nullptr, 16)));
    }
    frames.push_back(bytes);
  }
  return frames;
}

/// The receiver channel of `gpsemu --receiver MODEL --protocol ubx` behind a real pty, and the
/// frames PX4 wrote to that model (tests/data/px4/FILE).
class Px4PtyTest : public ::testing::Test {
 protected:
  /// `own`: the u-blox is the channel's protocol, as gpsemu's --receiver makes it (its summary lines
  /// then read it); otherwise it is added beside the channel's NMEA protocol, whose epochs write.
  Px4PtyTest(ReceiverModel model, std::chrono::milliseconds period, const std::string& file, bool own = false)
      : channel(channel_settings(ubx_settings(model, period), own), t0),
        frames(recorded_frames(std::string(GPSEMU_SOURCE_DIR) + "/tests/data/px4/" + file)) {
    if (!own) channel.add_protocol(std::make_unique<protocol::UbloxProtocol>(ubx_settings(model, period)));
    std::vector<std::unique_ptr<transport::Output>> outputs;
    auto pty = std::make_unique<transport::PtyOutput>();
    out = pty.get();
    outputs.push_back(std::move(pty));
    i = sink.add(std::move(outputs));
    sink.attach_client_input(i, &channel);
  }
  ~Px4PtyTest() override {
    if (client >= 0) ::close(client);
  }
  static ubx::SessionSettings ubx_settings(ReceiverModel model, std::chrono::milliseconds period) {
    ubx::SessionSettings settings;  // NAV-PVT every solution, no NMEA from the u-blox part
    settings.start.model = model;
    settings.start.sentences = {};
    settings.start.measurement_period = period;
    return settings;
  }
  static ChannelSettings channel_settings(const ubx::SessionSettings& ubx, bool own) {
    ChannelSettings settings;
    settings.origin = {43.0725, -89.4125, 260.0};
    if (own) settings.protocol = protocol::ublox_protocol(ubx);
    return settings;
  }
  void open_client() {
    client = ::open(out->device_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    ASSERT_GE(client, 0);
    termios tio{};
    ASSERT_EQ(::tcgetattr(client, &tio), 0);
    ::cfmakeraw(&tio);
    ASSERT_EQ(::tcsetattr(client, TCSANOW, &tio), 0);
  }
  /// The driver writes `frame`; the loop services the readable pty and writes the answer at once.
  void driver_writes(const std::string& frame) {
    const std::uint64_t before = out->stats().replies_written;
    ASSERT_EQ(::write(client, frame.data(), frame.size()), static_cast<ssize_t>(frame.size()));
    const auto until = std::chrono::steady_clock::now() + 2s;
    while (out->stats().replies_written == before && std::chrono::steady_clock::now() < until) {
      sink.service_all();
      std::this_thread::sleep_for(1ms);
    }
    ASSERT_EQ(out->stats().replies_written, before + 1);
  }
  /// What PX4 waits for after `sent`: MON-VER for the poll, ACK-NAK for the VALSET an M8 does not
  /// know, else ACK-ACK of that message; checked against the first frame the driver reads.
  static void expect_answer(const ubx::Frame& sent, const std::vector<ubx::Frame>& got, std::size_t line) {
    const ubx::MessageId want = sent.id == ubx::msg::mon_ver      ? ubx::msg::mon_ver
                                : sent.id == ubx::msg::cfg_valset ? ubx::msg::ack_nak
                                                                  : ubx::msg::ack_ack;
    ASSERT_FALSE(got.empty()) << "no answer to line " << line;
    EXPECT_EQ(got[0].id, want) << "line " << line;
    if (want != ubx::msg::mon_ver) {
      EXPECT_EQ(got[0].payload, std::string({static_cast<char>(sent.id.msg_class), static_cast<char>(sent.id.msg_id)}))
          << "line " << line;
    }
  }

  const UtcNs t0 = parse_iso8601_utc("2026-11-28T05:36:46Z");
  Channel channel;
  Sink sink;
  transport::PtyOutput* out = nullptr;
  std::size_t i = 0;
  int client = -1;
  const std::vector<std::string> frames;
};

/// `gpsemu --receiver ublox-m8n --protocol ubx --rate 5`.
class Px4ConfigurePty : public Px4PtyTest {
 protected:
  Px4ConfigurePty() : Px4PtyTest(ReceiverModel::ublox_m8n, 200ms, "neo_m8n_configure.txt") {}
};

/// `gpsemu --receiver ublox-m10 --protocol ubx --rate 10`.
class Px4ConfiguresAnM10Pty : public Px4PtyTest {
 protected:
  Px4ConfiguresAnM10Pty() : Px4PtyTest(ReceiverModel::ublox_m10, 100ms, "max_m10s_configure.txt", true) {}
};

TEST_F(Px4ConfigurePty, EveryFramePx4WaitsForIsAnsweredThoughTheLoopChecksThePtyBeforeItReads) {
  ASSERT_EQ(frames.size(), 12u);
  open_client();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const auto sent = frames_in(frames[k]);
    ASSERT_EQ(sent.size(), 1u) << "line " << k;
    sink.prepare(i);  // the loop's check at an epoch: the client has read everything
    driver_writes(frames[k]);
    sink.prepare(i);    // the next epoch's check, before the driver has read the answer
    sink.write(i, "");  // an epoch with nothing to send: every message off while PX4 configures
    const auto got = frames_in(test::read_available(client, 20ms, 1s));
    expect_answer(sent[0], got, k);
    EXPECT_EQ(got.size(), 1u) << "line " << k;
  }
  EXPECT_EQ(out->pty_stats().stale_bytes_discarded, 0u);
}

TEST_F(Px4ConfigurePty, ThePortOpenedAfterAnEpochWentInLosesNoAnswerAtTheNextCheck) {
  // PX4 opens the port between epochs: an epoch went into the pty while nobody had it open. The
  // driver reads it (its 20 ms flush), then probes: the VALSET's NAK, the CFG-PRTs' ACKs and the
  // MON-VER answer come while the loop checks the pty for the next epoch.
  ASSERT_GE(frames.size(), 4u);
  sink.prepare(i);
  (void)channel.step(t0, sources::Truth{});
  sink.write(i, channel.bytes());
  open_client();
  EXPECT_FALSE(test::read_available(client, 20ms, 1s).empty());  // the epoch written before it opened
  for (std::size_t k = 0; k < 4; ++k) {
    const auto sent = frames_in(frames[k]);
    ASSERT_EQ(sent.size(), 1u) << "line " << k;
    driver_writes(frames[k]);
    sink.prepare(i);  // the next epoch's check, before the driver has read the answer
    (void)channel.step(t0 + std::chrono::milliseconds(200 * (k + 1)), sources::Truth{});
    sink.write(i, channel.bytes());
    expect_answer(sent[0], frames_in(test::read_available(client, 20ms, 1s)), k);
  }
}

TEST_F(Px4ConfiguresAnM10Pty, EveryVALSETIsAckedButTheRtkKeyAMaxM10sLacks) {
  // PX4 on an M10 (Board::u_blox10 from MON-VER's hwVersion 000A0000): no USB or RTCM3 keys, the
  // default 100 ms, and CFG-NAVHPG-DGNSSMODE 3 as to every u-blox 9+ ("RTK, optional, as only RTK
  // devices like F9P support it": it takes the NAK). A MAX-M10S's standard-precision firmware
  // (SPG 5.10) has no CFG-NAVHPG group and NAKs the VALSET naming it; every other VALSET is ACKed
  // (PX4 requires the ACK of the probe, the navigation and rate keys, the message rates and the
  // I2C protocols).
  ASSERT_EQ(frames.size(), 9u);
  open_client();
  std::vector<ubx::MessageId> answers;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const auto sent = frames_in(frames[k]);
    ASSERT_EQ(sent.size(), 1u) << "line " << k;
    sink.prepare(i);
    driver_writes(frames[k]);
    sink.prepare(i);
    sink.write(i, "");
    const auto got = frames_in(test::read_available(client, 20ms, 1s));
    ASSERT_EQ(got.size(), 1u) << "line " << k;
    answers.push_back(got[0].id);
    if (sent[0].id == ubx::msg::mon_ver) {
      EXPECT_EQ(got[0].payload.substr(30, 8), "000A0000");  // hwVersion: PX4's Board::u_blox10
      EXPECT_NE(got[0].payload.find("MOD=MAX-M10S"), std::string::npos);
    } else {
      const std::string acked{static_cast<char>(sent[0].id.msg_class), static_cast<char>(sent[0].id.msg_id)};
      EXPECT_EQ(got[0].payload, acked) << "line " << k;
    }
  }
  const ubx::MessageId ack = ubx::msg::ack_ack, nak = ubx::msg::ack_nak, ver = ubx::msg::mon_ver;
  EXPECT_EQ(answers, (std::vector<ubx::MessageId>{ack, ack, ver, ack, nak, ack, ack, ack, ack}));
  EXPECT_EQ(out->pty_stats().stale_bytes_discarded, 0u);

  // Configured, PX4 injects RTCM3 into it as into any u-blox; a MAX-M10S has no RTCM3 input: no
  // answer, and the exit summary says the model is why (not the port's input protocols).
  const std::string rtcm = rtk::rtcm3_frame_bytes(rtk::encode_msm(1074, 42, 345600000u, 10, 1));
  ASSERT_EQ(::write(client, rtcm.data(), rtcm.size()), static_cast<ssize_t>(rtcm.size()));
  const auto until = std::chrono::steady_clock::now() + 2s;
  while (client_input_summary(channel).find("1 RTCM3 frames") == std::string::npos &&
         std::chrono::steady_clock::now() < until) {
    sink.service_all();
    std::this_thread::sleep_for(1ms);
  }
  EXPECT_NE(client_input_summary(channel).find("1 RTCM3 frames (0 bad CRC, 1 ignored: ublox-m10 takes no RTCM3)"),
            std::string::npos)
      << client_input_summary(channel);
}

}  // namespace px4_configure_pty_test
}  // namespace
}  // namespace gpsemu
