// Shared by the UBX tests (tests/unit/ubx, the pipeline tests): hex <-> bytes, frames from
// class/id/payload, the frames a byte string holds, and the answers of the configuration machine.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/solution_grid.hpp"

namespace gpsemu::ubx::test {

/// "b562 0107" -> bytes; spaces are ignored.
inline std::string unhex(std::string_view hex) {
  std::string out;
  int high = -1;
  for (const char c : hex) {
    if (c == ' ') continue;
    const int v = c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10;
    if (high < 0) {
      high = v;
    } else {
      out.push_back(static_cast<char>(high * 16 + v));
      high = -1;
    }
  }
  return out;
}

inline std::string hex(std::string_view bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (const char c : bytes) {
    out.push_back(digits[(static_cast<unsigned char>(c) >> 4) & 0xF]);
    out.push_back(digits[static_cast<unsigned char>(c) & 0xF]);
  }
  return out;
}

/// Every UBX frame in `bytes`, in order.
inline std::vector<Frame> frames_in(std::string_view bytes) {
  FrameReader reader;
  std::vector<Frame> out;
  for (ClientMessage& m : reader.feed(bytes)) {
    if (auto* f = std::get_if<Frame>(&m)) out.push_back(std::move(*f));
  }
  return out;
}

inline Frame ack_of(MessageId id) { return {msg::ack_ack, std::string{static_cast<char>(id.msg_class), static_cast<char>(id.msg_id)}}; }
inline Frame nak_of(MessageId id) { return {msg::ack_nak, std::string{static_cast<char>(id.msg_class), static_cast<char>(id.msg_id)}}; }

/// What the receiver answered to one client message.
struct Exchange {
  std::vector<Frame> frames;
  std::vector<Effect> effects;
};

/// Writes the frame of `id` with `payload` to `machine`.
inline Exchange send(ConfigMachine& machine, MessageId id, std::string_view payload = {}) {
  Answer answer = machine.feed(frame_bytes(id, payload));
  return {frames_in(answer.bytes), std::move(answer.effects)};
}

struct KeyValue {
  std::uint32_t key;
  std::uint64_t value;
};
/// A CFG-VALSET payload (version 0, `layers`, the keys with their sizes).
inline std::string valset(std::initializer_list<KeyValue> items, std::uint8_t layers = 0x01) {
  std::string p;
  put_u1(p, 0);
  put_u1(p, layers);
  put_zeros(p, 2);
  for (const KeyValue& kv : items) {
    put_u4(p, kv.key);
    put_le(p, kv.value, static_cast<int>(key_value_bytes(kv.key)));
  }
  return p;
}
/// A CFG-VALGET poll payload (version 0, `layer`, position 0, the keys).
inline std::string valget(std::initializer_list<std::uint32_t> keys, std::uint8_t layer = 0) {
  std::string p;
  put_u1(p, 0);
  put_u1(p, layer);
  put_u2(p, 0);
  for (const std::uint32_t k : keys) put_u4(p, k);
  return p;
}

/// The effects of type T in `effects`.
template <class T>
std::vector<T> effects_of(const std::vector<Effect>& effects) {
  std::vector<T> out;
  for (const Effect& e : effects) {
    if (const auto* t = std::get_if<T>(&e)) out.push_back(*t);
  }
  return out;
}

/// The epochs a receiver of `model` with settings `s` has (solution_grid.hpp): every `period`,
/// from the top of the second on (so at 200 ms: .000 .200 .400 ...).
inline void expect_solutions_every(const Settings& s, ReceiverModel model, std::chrono::milliseconds period) {
  using namespace std::chrono;
  const SolutionGrid grid = solution_grid(s, model);
  EXPECT_EQ(grid.period, period);
  const SolutionTime second = time_point_cast<nanoseconds>(sys_days{year{2026} / November / 24} + hours{12});
  EXPECT_TRUE(grid.contains(second));
  EXPECT_EQ(grid.next_after(second), second + period);
  EXPECT_EQ(grid.next_after(second + period / 2), second + period);
}

}  // namespace gpsemu::ubx::test
