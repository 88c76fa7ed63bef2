// The replay loop (emulator/replay/replayer.hpp) on a fake clock and a recording output:
// deadlines from the log's own times divided by the speed, steps back and gaps, --loop,
// --duration, --fast, --retime (stamps, phase, checksums) and the options it refuses.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/replay/replayer.hpp"
#include "nmea/sentences.hpp"
#include "transport/recording_output.hpp"

namespace gpsemu::replay {
namespace {
namespace pacing_test {

using namespace std::chrono;

std::string s(const std::string& body) { return fmt::format("${}*{:02X}\r\n", body, nmea::checksum(body)); }
std::string epoch(const std::string& time) {
  return s(fmt::format("GPRMC,{},A,4304.35012,N,08924.75027,W,0.000,,010524,,,A,V", time)) +
         s(fmt::format("GPGGA,{},4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,", time)) +
         s("GPGSA,A,3,01,02,03,04,,,,,,,,,1.5,0.9,1.2");
}

/// A wall clock that jumps to each deadline it is asked to sleep until.
class FakeIo final : public ClockIo {
 public:
  explicit FakeIo(UtcNs start) : t(start) {}
  UtcNs now() override { return t; }
  void sleep_until(UtcNs deadline, const std::atomic<bool>&) override {
    sleeps.push_back(deadline);
    t = std::max(t, deadline);
  }
  void wait_for_input(nanoseconds timeout, const std::atomic<bool>&) override { t += timeout; }
  UtcNs t;
  std::vector<UtcNs> sleeps;
};

struct Replayed {
  std::vector<std::string> epochs;
  std::vector<UtcNs> sleeps;
  UtcNs start;
  UtcNs first_stamp;
  ReplayStats stats;
};

Replayed replay(const std::string& log_text, Config config, UtcNs start = parse_iso8601_utc("2030-01-01T08:00:00.3Z")) {
  FakeIo io(start);
  auto recording = std::make_unique<transport::RecordingOutput>();
  auto* out = recording.get();
  std::vector<std::unique_ptr<transport::Output>> outputs;
  outputs.push_back(std::move(recording));
  Replayer r(config.timeline, config.replay, std::make_unique<LogStream>(log_text, "test.nmea"), std::move(outputs), io);
  const std::atomic<bool> stop{false};
  EXPECT_EQ(r.run(stop), 0);
  return {out->epochs, io.sleeps, start, r.first_stamp(), r.stats()};
}

/// Deadlines relative to the first one, in milliseconds.
std::vector<double> offsets_ms(const std::vector<UtcNs>& sleeps) {
  std::vector<double> v;
  for (const auto& d : sleeps) v.push_back(duration<double, std::milli>(d - sleeps.front()).count());
  return v;
}

TEST(ReplayPacing, AtSpeed10EpochsAreDue100msApartAndSentUnchangedWithGapsAndStepsBackAsRecorded) {
  const std::string log = epoch("120000.00") + epoch("120001.00") + epoch("120002.00") + epoch("120005.00") +
                          epoch("120004.50") + epoch("120006.00");
  Config config;
  config.replay.speed = 10.0;
  const Replayed run = replay(log, config);
  ASSERT_EQ(run.epochs.size(), 6u);
  EXPECT_EQ(run.epochs[0], epoch("120000.00"));
  EXPECT_EQ(run.epochs[4], epoch("120004.50"));
  const std::vector<double> expected{0, 100, 200, 500, 450, 600};
  ASSERT_EQ(run.sleeps.size(), 6u);
  const auto got = offsets_ms(run.sleeps);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(got[i], expected[i], 1e-6) << i;
  EXPECT_EQ(run.sleeps.front(), run.start) << "the first epoch goes out at once";
  EXPECT_EQ(run.stats.worst_delay, nanoseconds::zero()) << "the step back is due with the previous epoch: not late";
}

TEST(ReplayPacing, LoopStartsOverOnePeriodAfterTheLastEpochAndDurationStopsIt) {
  const std::string log = epoch("120000.00") + epoch("120001.00") + epoch("120002.00");
  Config config;
  config.replay.loop = true;
  config.timeline.duration_s = 7.5;  // log time: 0 1 2 | 3 4 5 | 6 7 (8 is past 7.5)
  const Replayed run = replay(log, config);
  ASSERT_EQ(run.epochs.size(), 8u);
  EXPECT_EQ(run.epochs[3], run.epochs[0]);
  const auto got = offsets_ms(run.sleeps);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], 1000.0 * static_cast<double>(i), 1e-6) << i;
  EXPECT_EQ(run.stats.passes, 3u);
}

TEST(ReplayPacing, FromToSelectTheRangeAndFastDoesNotWait) {
  const std::string log = epoch("120000.00") + epoch("120001.00") + epoch("120002.00") + epoch("120003.00");
  Config config;
  config.timeline.clock.kind = ClockKind::fast;
  config.replay.from = parse_log_position("from", "12:00:01");
  config.replay.to = parse_log_position("to", "2");
  const Replayed run = replay(log, config);
  ASSERT_EQ(run.epochs.size(), 2u);
  EXPECT_EQ(run.epochs[0], epoch("120001.00"));
  EXPECT_EQ(run.epochs[1], epoch("120002.00"));
  EXPECT_TRUE(run.sleeps.empty());
}

TEST(ReplayPacing, RetimeWithStartTimeStampsEpochsFromItAtTheLogsSpacing) {
  const std::string log = epoch("235959.00") + epoch("000000.00") + epoch("000001.00");
  Config config;
  config.replay.retime = true;
  config.replay.speed = 2.0;
  config.timeline.start_time = parse_iso8601_utc("2024-02-28T23:59:59Z");
  const Replayed run = replay(log, config);
  ASSERT_EQ(run.epochs.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto lines = run.epochs[i];
    for (std::size_t start = 0, nl; (nl = lines.find('\n', start)) != std::string::npos; start = nl + 1) {
      EXPECT_TRUE(nmea::parse_sentence(lines.substr(start, nl - start)).ok()) << lines;
    }
  }
  EXPECT_NE(run.epochs[0].find("$GPRMC,235959.00,A,4304.35012,N,08924.75027,W,0.000,,280224,"), std::string::npos);
  EXPECT_NE(run.epochs[1].find("$GPRMC,000000.00,A,4304.35012,N,08924.75027,W,0.000,,290224,"), std::string::npos)
      << "leap day after midnight";
  EXPECT_NE(run.epochs[2].find("$GPGGA,000001.00,"), std::string::npos);
  const auto got = offsets_ms(run.sleeps);
  EXPECT_NEAR(got[2], 1000.0, 1e-6) << "2 s of log at speed 2";
  EXPECT_EQ(run.sleeps.front(), run.start) << "with --start-time the first epoch goes out at once";
}

TEST(ReplayPacing, RetimeToThePresentKeepsTheLogsPhaseAndSendsAtStampPlusLatency) {
  const std::string log = epoch("105153.408") + epoch("105154.408");
  Config config;
  config.replay.retime = true;
  config.timeline.latency_s = 0.05;
  const UtcNs start = parse_iso8601_utc("2030-01-01T08:00:00.500Z");
  const Replayed run = replay(log, config, start);
  EXPECT_EQ(run.first_stamp, parse_iso8601_utc("2030-01-01T08:00:01.408Z"));
  ASSERT_EQ(run.sleeps.size(), 2u);
  EXPECT_EQ(run.sleeps[0], run.first_stamp + milliseconds(50));
  EXPECT_NE(run.epochs[0].find("$GPRMC,080001.408,A,"), std::string::npos) << run.epochs[0];
  EXPECT_NE(run.epochs[0].find(",010130,"), std::string::npos) << run.epochs[0];
  EXPECT_NE(run.epochs[1].find("$GPGGA,080002.408,"), std::string::npos) << run.epochs[1];
}

TEST(ReplayPacing, OtherClocksAndEmptyRangesAreRefusedNamingTheOption) {
  const std::string log = epoch("120000.00") + epoch("120001.00");
  Config config;
  config.timeline.clock = parse_clock_spec("scaled:2");
  EXPECT_THROW((void)check_replay_options(config.timeline, config.replay, *std::make_unique<LogStream>(log, "x")), std::invalid_argument);
  config.timeline.clock = {};
  config.replay.from = parse_log_position("from", "5");
  try {
    (void)check_replay_options(config.timeline, config.replay, *std::make_unique<LogStream>(log, "x"));
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--from: epoch 5 is past the end: the log has 2 epochs"), std::string::npos)
        << e.what();
  }
}

}  // namespace pacing_test
}  // namespace
}  // namespace gpsemu::replay
