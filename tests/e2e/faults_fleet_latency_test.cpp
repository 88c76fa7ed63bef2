// A `latency` fault in a fleet in real time: each delayed epoch leaves at its own moment between
// the epochs, as a single receiver's does (docs/faults.md), not with the next epoch. Two receivers
// at 2 Hz on real UDP sockets; the kernel's receive time stamp of every datagram against its GGA
// time: delay_ms after the epoch's deadline, well before the next epoch's (an order-of-magnitude
// check, 250 ms against 500 ms, not a timing measurement).
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/pipeline/runner.hpp"
#include "tests/support/nmea_check.hpp"
#include "tests/support/udp_socket.hpp"

namespace gpsemu {
namespace {
namespace faults_fleet_latency_test {

/// Seconds of the day of the GGA time "hhmmss.ss" in `datagram` (which holds one GGA).
double gga_seconds_of_day(const std::string& datagram) {
  const std::size_t at = datagram.find("GGA,");
  if (at == std::string::npos) return -1.0;
  return test::seconds_of_day(datagram.substr(at + 4, 9));
}

TEST(FaultsFleetLatency, EachDelayedEpochLeavesAtItsOwnTimeNotWithTheNextEpoch) {
  constexpr int kReceivers = 2;
  constexpr double kLatencyS = 0.05, kDelayS = 0.25, kPeriodS = 0.5;
  const auto sinks = test::stamped_sinks(kReceivers);
  std::string toml = fmt::format("rate = 2\nduration = 3\nlatency = {}\nsentences = \"GGA\"\nlog-level = \"warn\"\n"
                                 "[[fault]]\nkind = \"latency\"\ndelay_ms = {}\n",
                                 kLatencyS, kDelayS * 1000);
  toml += test::receivers_writing_to(sinks);
  Runner runner(build_config_from_text(toml, "fleet.toml", {}));
  std::atomic<bool> stop{false};
  ASSERT_EQ(runner.run(stop), 0);
  const auto emitted = runner.stats().epochs_emitted;
  ASSERT_GE(emitted, 4u);  // a loaded machine may skip one: counted in epochs_late_skipped
  for (int i = 0; i < kReceivers; ++i) {
    EXPECT_EQ(runner.receiver_stats(static_cast<std::size_t>(i)).epochs_delayed, emitted) << "receiver " << i;
    const auto got = sinks[static_cast<std::size_t>(i)]->drain_stamped();
    ASSERT_EQ(got.size(), emitted) << "receiver " << i << ": one datagram an epoch, each written on its own";
    std::vector<double> lags_s;
    double last_epoch = -1.0;
    for (const auto& d : got) {
      const std::string& datagram = d.bytes;
      const double arrived = d.seconds_of_day;
      ASSERT_EQ(std::count(datagram.begin(), datagram.end(), '$'), 1) << "one epoch a datagram: " << datagram;
      const double epoch = gga_seconds_of_day(datagram);
      EXPECT_GT(epoch, last_epoch) << "in order";
      last_epoch = epoch;
      double lag = arrived - epoch;
      if (lag < -43200) lag += 86400;  // across midnight
      EXPECT_GE(lag, kLatencyS + kDelayS - 0.002) << "left before its deadline + delay_ms: " << datagram;
      lags_s.push_back(lag);
    }
    std::nth_element(lags_s.begin(), lags_s.begin() + static_cast<std::ptrdiff_t>(lags_s.size() / 2), lags_s.end());
    const double median = lags_s[lags_s.size() / 2];
    // With the next epoch it would be kLatencyS + kPeriodS (0.55 s).
    EXPECT_LT(median, kLatencyS + kDelayS + (kPeriodS - kDelayS) * 0.8) << "receiver " << i << ": median lag " << median;
  }
}

}  // namespace faults_fleet_latency_test
}  // namespace
}  // namespace gpsemu
