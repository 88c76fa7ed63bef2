// What held up against a hostile client in issue 22 and must keep holding, in-process and fast:
// a sweep of every UBX class and id (65 536 ids x 3 payload lengths = 196 608 frames) through one
// u-blox session, each answered with whole frames, at most one ACK/NAK naming it, the receiver
// still sane afterwards; 0xFFFF lengths, truncated frames and byte-by-byte feeding, which find the
// same frames whatever the chunking; and the CFG edge matrix of docs/ublox.md (what is ACKed, what
// is NAKed with nothing changed).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/session.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace hostile_input_test {

using namespace std::chrono_literals;
using test::frames_in;
using test::unhex;

std::size_t bytes_of(const std::vector<Frame>& frames) {
  std::size_t n = 0;
  for (const Frame& f : frames) n += frame_overhead_bytes + f.payload.size();
  return n;
}

bool is_ack(const Frame& f) { return f.id == msg::ack_ack || f.id == msg::ack_nak; }

TEST(UbxHostileInput, EveryClassAndIdIsAnsweredWithWholeFramesAndLeavesTheReceiverSane) {
  SessionSettings settings;
  settings.start.model = ReceiverModel::ublox_f9p;
  Session session(settings);
  const std::vector<std::string> payloads{"", std::string(1, '\x01'), unhex("01 02 03 04")};
  std::uint64_t frames = 0, answered = 0, acks = 0;
  for (int c = 0; c < 256; ++c) {
    for (int i = 0; i < 256; ++i) {
      const MessageId id{static_cast<std::uint8_t>(c), static_cast<std::uint8_t>(i)};
      for (const std::string& payload : payloads) {
        session.client_wrote(frame_bytes(id, payload));
        ++frames;
        const std::string reply = session.take_reply();
        (void)session.take_effects();
        if (reply.empty()) continue;
        ++answered;
        const auto got = frames_in(reply);
        ASSERT_EQ(bytes_of(got), reply.size()) << "half a frame in the answer to " << c << "-" << i;
        std::size_t ack_count = 0;
        for (const Frame& f : got) {
          if (!is_ack(f)) continue;
          ++ack_count;
          ASSERT_EQ(f.payload, (std::string{static_cast<char>(c), static_cast<char>(i)}))
              << "an ACK/NAK naming another message than " << c << "-" << i;
        }
        ASSERT_LE(ack_count, 1u) << c << "-" << i;
        acks += ack_count;
      }
    }
  }
  EXPECT_EQ(frames, 196'608u);
  EXPECT_EQ(session.reader_stats().frames_ok, frames);
  EXPECT_EQ(session.reader_stats().bad_checksum, 0u);
  EXPECT_LE(session.polls_waiting(), 64u) << "NAV polls wait once a kind";
  // Still a receiver: MON-VER answered, CFG-RATE read back with a period it can run.
  session.client_wrote(frame_bytes(msg::mon_ver, ""));
  const auto ver = frames_in(session.take_reply());
  ASSERT_EQ(ver.size(), 1u);
  EXPECT_EQ(ver[0].id, msg::mon_ver);
  session.client_wrote(frame_bytes(msg::cfg_rate, ""));
  const auto rate = frames_in(session.take_reply());
  ASSERT_EQ(rate.size(), 2u);
  ASSERT_EQ(rate[0].payload.size(), 6u);
  const auto meas_ms = static_cast<std::uint8_t>(rate[0].payload[0]) | static_cast<std::uint8_t>(rate[0].payload[1]) << 8;
  const auto nav = static_cast<std::uint8_t>(rate[0].payload[2]) | static_cast<std::uint8_t>(rate[0].payload[3]) << 8;
  EXPECT_GE(meas_ms, 25);
  EXPECT_GE(nav, 1);
  EXPECT_LE(nav, 127);
  std::printf("figure: sweep of %llu frames: %llu answered, %llu ACK/NAK\n", static_cast<unsigned long long>(frames),
              static_cast<unsigned long long>(answered), static_cast<unsigned long long>(acks));
}

/// Frames and counts a reader finds in `stream` fed in the chunks `sizes` gives (cycled).
struct Found {
  std::vector<MessageId> ids;
  FrameStats stats;
};
Found read_in_chunks(const std::string& stream, const std::vector<std::size_t>& sizes) {
  FrameReader reader;
  Found found;
  std::size_t at = 0, k = 0;
  while (at < stream.size()) {
    const std::size_t n = std::min(sizes[k++ % sizes.size()], stream.size() - at);
    for (const ClientMessage& m : reader.feed(std::string_view(stream).substr(at, n))) {
      if (const Frame* f = std::get_if<Frame>(&m)) found.ids.push_back(f->id);
    }
    at += n;
  }
  found.stats = reader.stats();
  return found;
}

TEST(UbxHostileInput, MaximumLengthsTruncationAndByteByByteFindTheSameFramesWhateverTheChunking) {
  const std::string stream = unhex("b562 0601 ffff") + frame_bytes(msg::mon_ver, "") +  // 0xFFFF announced
                             unhex("b562 0608 6400") + std::string(10, '\x01') +          // 100 announced, 10 sent
                             std::string(100, '\0') +  // the rest of it, its bad checksum, then 8 zeros
                             frame_bytes(msg::cfg_rate, "") +
                             frame_bytes(msg::cfg_valset, std::string(max_client_payload_bytes, '\0')) +
                             unhex("b562 068a 0104") + std::string(1027, '\0') +  // 1025: one byte too long
                             frame_bytes(msg::cfg_prt, unhex("01")) + unhex("b562 0104 0a00 0102");  // ends mid-frame
  const std::vector<MessageId> expected{msg::mon_ver, msg::cfg_rate, msg::cfg_valset, msg::cfg_prt};
  std::mt19937 random(22);
  std::vector<std::size_t> random_sizes;
  for (int k = 0; k < 1000; ++k) random_sizes.push_back(1 + random() % 40);
  for (const auto& sizes : {std::vector<std::size_t>{stream.size()}, std::vector<std::size_t>{1},
                            std::vector<std::size_t>{2, 3, 5, 7}, random_sizes}) {
    const Found found = read_in_chunks(stream, sizes);
    EXPECT_EQ(found.ids, expected) << "chunks of " << sizes.front();
    EXPECT_EQ(found.stats.too_long, 2u) << "0xFFFF and 1025 bytes announced";
    EXPECT_EQ(found.stats.bad_checksum, 1u) << "the truncated frame, completed by what followed";
    EXPECT_EQ(found.stats.frames_ok, expected.size());
  }
}

enum class Reply { ack, nak };
struct EdgeCase {
  const char* what;
  ReceiverModel model;
  MessageId id;
  std::string payload;
  Reply reply;
};

std::string rate(std::uint16_t meas_ms, std::uint16_t nav_cycles, std::uint16_t time_ref) {
  std::string p;
  put_u2(p, meas_ms);
  put_u2(p, nav_cycles);
  put_u2(p, time_ref);
  return p;
}
/// CFG-NAV5 with `mask`, dynModel and fixMode (the rest zero).
std::string nav5(std::uint16_t mask, std::uint8_t dyn_model, std::uint8_t fix_mode) {
  std::string p;
  put_u2(p, mask);
  put_u1(p, dyn_model);
  put_u1(p, fix_mode);
  put_zeros(p, 32);
  return p;
}
std::string cfg_msg3(MessageId of, std::uint8_t every) {
  return std::string{static_cast<char>(of.msg_class), static_cast<char>(of.msg_id), static_cast<char>(every)};
}
std::string valset_many(std::size_t keys) {
  std::string p = test::valset({});
  for (std::size_t k = 0; k < keys; ++k) {
    put_u4(p, key::rate_meas);
    put_u2(p, 200);
  }
  return p;
}

std::vector<EdgeCase> edge_matrix() {
  using M = ReceiverModel;
  std::vector<EdgeCase> cases{
      {"rate 25 ms, the protocol minimum", M::ublox_m8n, msg::cfg_rate, rate(25, 1, 0), Reply::ack},
      {"rate 24 ms", M::ublox_m8n, msg::cfg_rate, rate(24, 1, 0), Reply::nak},
      {"rate 0 ms", M::ublox_f9p, msg::cfg_rate, rate(0, 1, 0), Reply::nak},
      {"rate 65535 ms", M::ublox_f9p, msg::cfg_rate, rate(65535, 1, 0), Reply::ack},
      {"navRate 0", M::ublox_m8n, msg::cfg_rate, rate(100, 0, 0), Reply::nak},
      {"navRate 127", M::ublox_m8n, msg::cfg_rate, rate(100, 127, 0), Reply::ack},
      {"navRate 128", M::ublox_m9n, msg::cfg_rate, rate(100, 128, 0), Reply::nak},
      {"navRate 65535", M::ublox_m9n, msg::cfg_rate, rate(100, 65535, 0), Reply::nak},
      {"65535 ms x 127", M::ublox_f9p, msg::cfg_rate, rate(65535, 127, 0), Reply::ack},
      {"timeRef 5", M::ublox_f9p, msg::cfg_rate, rate(1000, 1, 5), Reply::ack},
      {"timeRef 6", M::ublox_f9p, msg::cfg_rate, rate(1000, 1, 6), Reply::nak},
      {"timeRef 65535", M::ublox_m8n, msg::cfg_rate, rate(1000, 1, 65535), Reply::nak},
      {"CFG-RATE of 4 bytes", M::ublox_m8n, msg::cfg_rate, unhex("6400 0100"), Reply::nak},
      {"40 ms on an M8N (faster than it can: acknowledged)", M::ublox_m8n, msg::cfg_rate, rate(40, 1, 0), Reply::ack},
      {"CFG-MSG 3 bytes NAV-PVT", M::ublox_m8n, msg::cfg_msg, cfg_msg3(msg::nav_pvt, 1), Reply::ack},
      {"CFG-MSG 3 bytes NAV-PVT every 255th", M::ublox_f9p, msg::cfg_msg, cfg_msg3(msg::nav_pvt, 255), Reply::ack},
      {"CFG-MSG 8 bytes NAV-PVT", M::ublox_f9p, msg::cfg_msg, cfg_msg3(msg::nav_pvt, 0) + unhex("01 00 00 00 00"),
       Reply::ack},
      {"CFG-MSG NAV-SVINFO on an F9P", M::ublox_f9p, msg::cfg_msg, cfg_msg3(msg::nav_svinfo, 1), Reply::nak},
      {"CFG-MSG NAV-SVINFO on an M8N", M::ublox_m8n, msg::cfg_msg, cfg_msg3(msg::nav_svinfo, 1), Reply::ack},
      {"CFG-MSG NAV-HPPOSLLH on an M8N", M::ublox_m8n, msg::cfg_msg, cfg_msg3(msg::nav_hpposllh, 1), Reply::nak},
      {"CFG-MSG NAV-HPPOSLLH on an M9N", M::ublox_m9n, msg::cfg_msg, cfg_msg3(msg::nav_hpposllh, 1), Reply::nak},
      {"CFG-MSG NAV-HPPOSLLH on an F9P", M::ublox_f9p, msg::cfg_msg, cfg_msg3(msg::nav_hpposllh, 1), Reply::ack},
      {"CFG-MSG NAV-SIG on an M8N", M::ublox_m8n, msg::cfg_msg, cfg_msg3(msg::nav_sig, 1), Reply::nak},
      {"CFG-MSG NAV-SIG on an M9N", M::ublox_m9n, msg::cfg_msg, cfg_msg3(msg::nav_sig, 1), Reply::ack},
      {"CFG-NAV5 dynModel 0", M::ublox_m8n, msg::cfg_nav5, nav5(0x0001, 0, 0), Reply::ack},
      {"CFG-NAV5 dynModel 1", M::ublox_m8n, msg::cfg_nav5, nav5(0x0001, 1, 0), Reply::nak},
      {"CFG-NAV5 dynModel 13", M::ublox_f9p, msg::cfg_nav5, nav5(0x0001, 13, 0), Reply::nak},
      {"CFG-NAV5 dynModel 255", M::ublox_f9p, msg::cfg_nav5, nav5(0x0001, 255, 0), Reply::nak},
      {"CFG-NAV5 fixMode 0", M::ublox_m8n, msg::cfg_nav5, nav5(0x0004, 0, 0), Reply::nak},
      {"CFG-NAV5 fixMode 4", M::ublox_m8n, msg::cfg_nav5, nav5(0x0004, 0, 4), Reply::nak},
      {"CFG-NAV5 dynModel 1 outside the mask", M::ublox_m8n, msg::cfg_nav5, nav5(0x0004, 1, 3), Reply::ack},
      {"CFG-VALSET on an M8N", M::ublox_m8n, msg::cfg_valset, test::valset({{key::rate_meas, 200}}), Reply::nak},
      {"CFG-VALSET rate 200 ms", M::ublox_f9p, msg::cfg_valset, test::valset({{key::rate_meas, 200}}), Reply::ack},
      {"CFG-VALSET rate 10 ms", M::ublox_f9p, msg::cfg_valset, test::valset({{key::rate_meas, 10}}), Reply::nak},
      {"CFG-VALSET an unknown key", M::ublox_f9p, msg::cfg_valset, test::valset({{0x20FF0001, 1}}), Reply::nak},
      {"CFG-VALSET 64 keys", M::ublox_f9p, msg::cfg_valset, valset_many(64), Reply::ack},
      {"CFG-VALSET 65 keys", M::ublox_f9p, msg::cfg_valset, valset_many(65), Reply::nak},
      {"CFG-VALGET layer 7", M::ublox_f9p, msg::cfg_valget, test::valget({key::rate_meas}, 7), Reply::ack},
      {"CFG-VALGET layer 0x55", M::ublox_f9p, msg::cfg_valget, test::valget({key::rate_meas}, 0x55), Reply::nak},
      {"CFG-VALGET on an M8N", M::ublox_m8n, msg::cfg_valget, test::valget({key::rate_meas}), Reply::nak},
      {"CFG-VALDEL from RAM", M::ublox_f9p, msg::cfg_valdel, test::valget({key::rate_meas}, 0x01), Reply::nak},
  };
  for (std::uint16_t meas : {25, 50, 100, 125, 200, 1000, 2000, 10000, 30000, 65535}) {
    cases.push_back({"a period the protocol allows", ReceiverModel::ublox_f9p, msg::cfg_rate, rate(meas, 1, 1), Reply::ack});
  }
  for (std::uint8_t dyn = 2; dyn <= 12; ++dyn) {
    cases.push_back({"CFG-NAV5 dynModel 2..12", ReceiverModel::ublox_m8n, msg::cfg_nav5, nav5(0x0001, dyn, 0), Reply::ack});
  }
  for (std::uint8_t fix = 1; fix <= 3; ++fix) {
    cases.push_back({"CFG-NAV5 fixMode 1..3", ReceiverModel::ublox_f9p, msg::cfg_nav5, nav5(0x0004, 0, fix), Reply::ack});
  }
  return cases;
}

TEST(UbxHostileInput, TheCfgEdgeMatrixIsAckedOrNakedAsDocumented) {
  const std::vector<EdgeCase> cases = edge_matrix();
  for (const EdgeCase& e : cases) {
    StartSettings start;
    start.model = e.model;
    ConfigMachine machine(start);
    const Settings before = machine.settings();
    const auto got = test::send(machine, e.id, e.payload);
    ASSERT_FALSE(got.frames.empty()) << e.what;
    const Frame& last = got.frames.back();
    EXPECT_EQ(last, e.reply == Reply::ack ? test::ack_of(e.id) : test::nak_of(e.id)) << e.what;
    if (e.reply == Reply::nak) {
      EXPECT_TRUE(got.effects.empty()) << e.what << ": a NAK changes nothing";
      EXPECT_EQ(machine.settings().output_period(), before.output_period()) << e.what;
    }
  }
  std::printf("figure: CFG edge matrix of %zu cases\n", cases.size());
}

}  // namespace hostile_input_test
}  // namespace
}  // namespace gpsemu::ubx
