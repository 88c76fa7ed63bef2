// The byte-level faults at the channel's encoded epoch, before any transport: garble corrupts the
// epoch's sentences (deterministic from the seed), latency holds the epoch's bytes back until
// their time comes, in order, with the epoch's own time fields.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "emulator/pipeline/channel.hpp"
#include "nmea/parse.hpp"

namespace gpsemu {
namespace {
namespace channel_byte_faults_test {

using std::chrono::milliseconds;
using std::chrono::seconds;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

ChannelSettings with(const std::vector<faults::Fault>& faults) {
  ChannelSettings s;
  s.origin = {43.0725, -89.4125, 260.0};
  s.seed = 11;
  s.faults.faults = faults;
  return s;
}

faults::Fault make(const faults::FaultKeys& keys) { return faults::make_fault(keys); }

std::size_t valid_sentences(const std::string& bytes) {
  nmea::StreamReader reader;
  return reader.feed(bytes).size();
}

TEST(ChannelByteFaults, GarbleCorruptsItsEpochsOnlyAndTheSameSeedGivesTheSameBytes) {
  const std::vector<faults::Fault> faults{make({{"kind", "garble"}, {"at", 1.0}, {"duration", 1.0}, {"rate", 1.0}})};
  Channel a(with(faults), kT0), b(with(faults), kT0), clean(with({}), kT0);
  std::vector<std::string> bytes_a, bytes_b, bytes_clean;
  for (int s = 0; s < 3; ++s) {
    (void)a.step(kT0 + seconds(s), sources::Truth{});
    (void)b.step(kT0 + seconds(s), sources::Truth{});
    (void)clean.step(kT0 + seconds(s), sources::Truth{});
    bytes_a.push_back(a.bytes());
    bytes_b.push_back(b.bytes());
    bytes_clean.push_back(clean.bytes());
  }
  EXPECT_EQ(bytes_a, bytes_b);
  EXPECT_EQ(bytes_a[0], bytes_clean[0]);
  EXPECT_EQ(bytes_a[2], bytes_clean[2]);
  EXPECT_GT(valid_sentences(bytes_clean[1]), 2u);
  EXPECT_EQ(valid_sentences(bytes_a[1]), 0u);  // rate 1: every sentence broken
  EXPECT_EQ(a.stats().epochs_garbled, 1u);
  EXPECT_EQ(a.stats().units_flipped + a.stats().units_truncated, valid_sentences(bytes_clean[1]));
}

TEST(ChannelByteFaults, LatencyHoldsEachEpochBackUntilItsTimeInOrder) {
  Channel late(with({make({{"kind", "latency"}, {"at", 1.0}, {"duration", 2.0}, {"delay_ms", 1500.0}})}), kT0);
  Channel clean(with({}), kT0);
  std::vector<std::string> expected;
  for (int s = 0; s < 5; ++s) {
    (void)clean.step(kT0 + seconds(s), sources::Truth{});
    expected.push_back(clean.bytes());
  }
  (void)late.step(kT0, sources::Truth{});
  EXPECT_EQ(late.bytes(), expected[0]);
  EXPECT_FALSE(late.delayed_until());
  (void)late.step(kT0 + seconds(1), sources::Truth{});
  EXPECT_EQ(late.bytes(), "");  // held back 1.5 s
  EXPECT_EQ(late.delayed_until(), kT0 + milliseconds(2500));
  (void)late.step(kT0 + seconds(2), sources::Truth{});
  EXPECT_EQ(late.bytes(), "");
  // Between epochs, as the loop takes it on the wall clock: epoch 1's bytes at 2.5 s.
  EXPECT_EQ(late.take_delayed(kT0 + milliseconds(2400)), "");
  EXPECT_EQ(late.take_delayed(kT0 + milliseconds(2500)), expected[1]);
  // The fault is over at 3 s: epoch 3 waits behind epoch 2 (due at 3.5 s), never overtakes it.
  (void)late.step(kT0 + seconds(3), sources::Truth{});
  EXPECT_EQ(late.bytes(), "");
  EXPECT_EQ(late.delayed_until(), kT0 + milliseconds(3500));
  (void)late.step(kT0 + seconds(4), sources::Truth{});
  EXPECT_EQ(late.bytes(), expected[2] + expected[3] + expected[4]);  // the time fields are the epochs' own
  EXPECT_FALSE(late.delayed_until());
  EXPECT_EQ(late.stats().epochs_delayed, 2u);
}

}  // namespace channel_byte_faults_test
}  // namespace
}  // namespace gpsemu
