// Google Benchmark for the u-blox configuration machine (ubx/machine.hpp): what one client frame
// costs, so that a burst of configuration cannot stall the epoch loop (docs/performance.md).
// A CFG-MSG and a CFG-VALSET of 8 keys, each changing what it names, on an F9P whose RAM holds
// the start settings (about 60 message rates and 20 stored keys).
// Run: build/tests/bench/gpsemu_bench --benchmark_filter=ubx_
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/machine.hpp"

namespace {

using namespace gpsemu::ubx;

ConfigMachine f9p() {
  StartSettings start;
  start.model = ReceiverModel::ublox_f9p;
  return ConfigMachine(start);
}

/// 256 CFG-MSG frames: NAV and NMEA messages on and off on UART1.
std::string cfg_msg_frames() {
  std::string bytes;
  for (int k = 0; k < 256; ++k) {
    const std::uint8_t cls = k % 2 == 0 ? 0x01 : 0xF0;
    const std::uint8_t id = static_cast<std::uint8_t>(cls == 0x01 ? (k / 2) % 0x40 : (k / 2) % 0x0A);
    bytes += frame_bytes(msg::cfg_msg, std::string{static_cast<char>(cls), static_cast<char>(id), static_cast<char>((k / 4) % 2)});
  }
  return bytes;
}

/// 256 CFG-VALSET frames of 8 MSGOUT keys (UART1) each, rates alternating.
std::string valset_frames() {
  std::string bytes;
  for (int k = 0; k < 256; ++k) {
    std::string p;
    put_u1(p, 0);
    put_u1(p, 1);
    put_zeros(p, 2);
    for (const std::uint32_t key : {0x20910007u, 0x20910039u, 0x2091001Bu, 0x20910016u, 0x209100BBu, 0x209100ACu,
                                    0x209100C0u, 0x209100C5u}) {
      put_u4(p, key);
      put_u1(p, static_cast<std::uint32_t>(k % 2));
    }
    bytes += frame_bytes(msg::cfg_valset, p);
  }
  return bytes;
}

void run(benchmark::State& state, const std::string& bytes) {
  ConfigMachine m = f9p();
  for (auto _ : state) {
    Answer a = m.feed(bytes);
    benchmark::DoNotOptimize(a);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 256);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}

void ubx_cfg_msg_frames(benchmark::State& state) { run(state, cfg_msg_frames()); }
void ubx_valset_8_key_frames(benchmark::State& state) { run(state, valset_frames()); }

BENCHMARK(ubx_cfg_msg_frames);
BENCHMARK(ubx_valset_8_key_frames);

}  // namespace
