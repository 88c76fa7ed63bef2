// PPS edge timing through the PPS interface with the recording fake, in the real runner: each
// leading edge lands at its UTC second (the figure is measured and printed; a generous bound is
// asserted, machines are shared), each trailing edge one width later, and the NMEA stamped with
// second S follows pulse S. With --start-time the shift is a whole number of seconds.
#include <gtest/gtest.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "emulator/config/config.hpp"
#include "emulator/pipeline/runner.hpp"
#include "tests/support/nmea_check.hpp"
#include "transport/output.hpp"
#include "transport/recording_pps.hpp"

namespace gpsemu {
namespace {
namespace pps_timing_test {

using namespace std::chrono_literals;
using transport::PpsTime;
using transport::RecordingPps;

/// Records every epoch with the wall clock read when it was written.
class TimedOutput final : public transport::Output {
 public:
  struct Write {
    PpsTime time;
    std::string bytes;
  };
  std::vector<Write>* writes;
  explicit TimedOutput(std::vector<Write>* w) : writes(w) {}
  [[nodiscard]] std::string describe() const override { return "timed recording"; }

 protected:
  transport::WriteStatus write_bytes(std::string_view bytes, std::string&) override {
    writes->push_back({RecordingPps::now(), std::string(bytes)});
    return transport::WriteStatus::ok;
  }
};

struct PpsRun {
  std::vector<RecordingPps::Edge> edges;
  std::vector<TimedOutput::Write> writes;
  std::chrono::nanoseconds shift{0};  ///< epoch time minus wall time
  RunStats stats;
};

PpsRun run_with_pps(RawOptions options) {
  options.push_back({"log-level", {"warn"}});
  const Config config = build_config(std::nullopt, options);
  PpsRun result;
  auto pps = std::make_unique<RecordingPps>();
  RecordingPps* recorded = pps.get();
  RunnerIo io;
  io.outputs.push_back(std::make_unique<TimedOutput>(&result.writes));
  io.pps = std::move(pps);
  Runner runner(config, std::move(io));
  result.shift = runner.epoch_minus_wall();
  std::atomic<bool> stop{false};
  EXPECT_EQ(runner.run(stop), 0);
  result.edges = recorded->edges;
  result.stats = runner.stats();
  return result;
}

/// Seconds of the day of an NMEA time field "hhmmss.ss".
double seconds_of_day(const std::string& field) {
  if (field.size() < 6) return -1.0;
  return std::stod(field.substr(0, 2)) * 3600 + std::stod(field.substr(2, 2)) * 60 + std::stod(field.substr(4));
}

/// The time field of the first GGA or RMC of an epoch.
std::string stamp_of(const std::string& epoch) {
  for (const auto& s : test::split_sentences(epoch).sentences) {
    if (test::sentence_type(s) == "GGA" || test::sentence_type(s) == "RMC") return test::time_field(s);
  }
  return {};
}

double ms(std::chrono::nanoseconds d) { return std::chrono::duration<double, std::milli>(d).count(); }

std::chrono::nanoseconds sub_second(PpsTime t) { return t - std::chrono::floor<std::chrono::seconds>(t); }

/// Checks the pulse train against the NMEA and returns the leading-edge offsets from their second.
std::vector<std::chrono::nanoseconds> check_pulses_and_nmea(const PpsRun& run, std::chrono::nanoseconds width,
                                                           std::chrono::nanoseconds latency) {
  constexpr auto kBound = 50ms;  // generous: shared, noisy machines; the measured figure is printed
  std::vector<std::chrono::nanoseconds> offsets;
  EXPECT_FALSE(run.edges.empty());
  EXPECT_FALSE(run.edges.back().level) << "the run ended inside a pulse";
  for (std::size_t i = 0; i < run.edges.size(); ++i) {
    const auto& e = run.edges[i];
    EXPECT_EQ(e.level, i % 2 == 0) << "edges must alternate, leading first";
    if (!e.level) {
      // Trailing edge: one width after the second of the pulse.
      const auto off = sub_second(e.time) - width;
      EXPECT_GE(off, 0ns);
      EXPECT_LT(off, kBound) << "trailing edge " << i;
      continue;
    }
    const auto off = sub_second(e.time);
    offsets.push_back(off);
    EXPECT_LT(off, kBound) << "leading edge " << i << " is " << ms(off) << " ms after its second";
    // The NMEA stamped with this second: written after the edge, at about second + latency;
    // nothing stamped with this second or later went out before the edge.
    const auto second = std::chrono::floor<std::chrono::seconds>(e.time);
    const double stamped_s =
        std::fmod(std::chrono::duration<double>((second + run.shift).time_since_epoch()).count(), 86400.0);
    bool found = false;
    for (const auto& w : run.writes) {
      const double s = seconds_of_day(stamp_of(w.bytes));
      if (s >= stamped_s - 1e-6 && s < stamped_s + 0.5) {
        EXPECT_GT(w.time, e.time) << "NMEA stamped " << stamp_of(w.bytes) << " went out before its pulse";
      }
      if (std::abs(s - stamped_s) < 1e-6) {
        found = true;
        // Measured from the UTC second, not from the edge: a leading edge that the scheduler
        // woke late (a loaded machine) must not make an on-time NMEA look early.
        EXPECT_GE(w.time - second, latency - 1ms) << stamp_of(w.bytes);
        EXPECT_LT(w.time - second, latency + kBound) << stamp_of(w.bytes);
      }
    }
    EXPECT_TRUE(found) << "no NMEA stamped with the second of pulse " << i;
  }
  return offsets;
}

void report(const char* what, std::vector<std::chrono::nanoseconds> offsets, const PpsRun& run) {
  if (offsets.empty()) return;
  std::sort(offsets.begin(), offsets.end());
  std::printf("%s: %zu leading edges after their UTC second by median %.3f ms, max %.3f ms; runner's worst %.3f ms; "
              "%llu pulses skipped late\n",
              what, offsets.size(), ms(offsets[offsets.size() / 2]), ms(offsets.back()),
              ms(run.stats.pps_worst_edge_delay), static_cast<unsigned long long>(run.stats.pps_pulses_late_skipped));
}

TEST(PpsTimingTest, LeadingEdgesMarkTheSecondAndTheirNmeaFollows) {
  const PpsRun run = run_with_pps({{"rate", {"10"}}, {"duration", {"3.5"}}, {"latency", {"0.05"}}});
  EXPECT_EQ(run.shift, 0ns);
  const auto offsets = check_pulses_and_nmea(run, 100ms, 50ms);
  EXPECT_GE(offsets.size(), 3u);
  EXPECT_EQ(run.stats.pps_pulses, offsets.size());
  report("10 Hz, latency 50 ms, width 100 ms", offsets, run);
  // Every edge in order with the epochs: leading edge, then the epoch of that second.
  EXPECT_EQ(run.stats.epochs_emitted, 35u);
}

TEST(PpsTimingTest, ZeroLatencyStillPutsThePulseBeforeItsNmea) {
  const PpsRun run = run_with_pps({{"rate", {"5"}}, {"duration", {"2.2"}}, {"latency", {"0"}}, {"pps-width", {"0.2"}}});
  const auto offsets = check_pulses_and_nmea(run, 200ms, 0ns);
  EXPECT_GE(offsets.size(), 2u);
  report("5 Hz, latency 0, width 200 ms", offsets, run);
}

TEST(PpsTimingTest, StartTimeShiftIsAWholeNumberOfSecondsWithPps) {
  // 10 Hz from an epoch 0.3 s into a second: without PPS the shift would be whole epochs only.
  const PpsRun run = run_with_pps({{"rate", {"10"}}, {"duration", {"2.5"}}, {"start-time", {"2024-05-01T12:00:00.3Z"}}});
  EXPECT_EQ(run.shift % std::chrono::nanoseconds(1s), 0ns) << ms(run.shift) << " ms";
  ASSERT_FALSE(run.writes.empty());
  EXPECT_EQ(stamp_of(run.writes.front().bytes), "120000.30");
  const auto offsets = check_pulses_and_nmea(run, 100ms, 50ms);
  EXPECT_GE(offsets.size(), 2u);
  report("--start-time, 10 Hz", offsets, run);
}

}  // namespace pps_timing_test
}  // namespace
}  // namespace gpsemu
