// Scenario files at start-up (issue 33 points 4-6): every refusal names the file, the line of the
// key at fault and the key; a fault that could never start within --duration is refused; several
// --scenario files add up; two spoofs on one receiver at once are refused.
#include <gtest/gtest.h>

#include <string>

#include "emulator/config/config.hpp"
#include "tests/support/config_files.hpp"

namespace gpsemu {
namespace {
namespace scenario_test {

std::string write_temp(const std::string& name, const std::string& text) { return test::write_temp("gpsemu_scn_", name, text); }

std::string error_of(const RawOptions& cli) { return test::config_error_of(std::nullopt, cli); }

TEST(Scenario, AReceiverTheRunDoesNotHaveIsNamedWithFileLineAndKey) {
  const auto file = write_temp("r.toml", "[[fault]]\nkind = \"outage\"\nat = 1\nreceiver = 3\n");
  const std::string e = error_of({{"scenario", {file}}});
  EXPECT_NE(e.find("scenario file " + file + ":4: [[fault]]: receiver: there is no receiver 3 (receivers are 0..0"),
            std::string::npos)
      << e;
}

TEST(Scenario, AnErrorNamesTheLineOfItsKeyNotOfTheTable) {
  const auto file = write_temp("k.toml", "[[fault]]\nkind = \"jam\"\nat = 3\n\ndb = 25\nramp = 5\n");
  const std::string e = error_of({{"scenario", {file}}});
  EXPECT_NE(e.find("scenario file " + file + ":6: [[fault]]: ramp: not a parameter of jam"), std::string::npos) << e;
}

TEST(Scenario, ANumberWrittenAsAStringSaysItGotAString) {
  const auto file = write_temp("s.toml", "[[fault]]\nkind = \"jam\"\ndb = \"25\"\n");
  const std::string e = error_of({{"scenario", {file}}});
  EXPECT_NE(e.find(file + ":3: [[fault]]: db: expected a number, got the string \"25\" (write db = 25, without quotes)"),
            std::string::npos)
      << e;
}

TEST(Scenario, AFaultThatWouldNeverStartWithinTheDurationIsRefused) {
  const auto file = write_temp("late.toml", "[[fault]]\nkind = \"outage\"\nat = 100\nduration = 5\n");
  const std::string e = error_of({{"scenario", {file}}, {"duration", {"60"}}});
  EXPECT_NE(e.find(file + ":3: [[fault]]: at: 100 s is not before the end of the run (--duration 60 s)"), std::string::npos)
      << e;
  EXPECT_NO_THROW((void)build_config(std::nullopt, {{"scenario", {file}}, {"duration", {"101"}}}));
  EXPECT_NO_THROW((void)build_config(std::nullopt, {{"scenario", {file}}}));  // no --duration: runs until stopped
  // at_utc: known to be too late only when --start-time says when the run begins.
  const auto utc = write_temp("utc.toml", "[[fault]]\nkind = \"outage\"\nat_utc = \"2026-05-01T12:01:00Z\"\nduration = 5\n");
  const std::string u = error_of({{"scenario", {utc}}, {"duration", {"60"}}, {"start-time", {"2026-05-01T12:00:00Z"}}});
  EXPECT_NE(u.find(utc + ":3: [[fault]]: at_utc: 2026-05-01T12:01:00.000Z is not before the end of the run"), std::string::npos)
      << u;
  EXPECT_NO_THROW((void)build_config(std::nullopt, {{"scenario", {utc}}, {"duration", {"61"}}, {"start-time", {"2026-05-01T12:00:00Z"}}}));
}

TEST(Scenario, SeveralScenarioFilesAddUpInTheOrderGiven) {
  const auto a = write_temp("a.toml", "[[fault]]\nkind = \"outage\"\nat = 1\nduration = 2\n");
  const auto b = write_temp("b.toml", "[[fault]]\nkind = \"jam\"\nat = 5\ndb = 20\n");
  const Config c = build_config(std::nullopt, {{"scenario", {a, b}}});
  ASSERT_EQ(c.timeline.faults.size(), 2u);
  EXPECT_EQ(c.timeline.faults[0].kind(), faults::FaultKind::outage);
  EXPECT_EQ(c.timeline.faults[1].kind(), faults::FaultKind::jam);
}

TEST(Scenario, TwoSpoofsOnOneReceiverAtOnceAreRefused) {
  const std::string spoof = "[[fault]]\nkind = \"spoof\"\nat = 10\nduration = 20\nspeed_mps = 2\n";
  const auto both = write_temp("two.toml", spoof + spoof);
  const std::string e = error_of({{"scenario", {both}}});
  EXPECT_NE(e.find(both + ":7: [[fault]]: spoof: overlaps the spoof at scenario file " + both + ":1 on the same receiver from 10 s"),
            std::string::npos)
      << e;
  // One after the other (the first's fade included), or on different receivers: accepted.
  const auto after = write_temp("after.toml", spoof + "ramp_out_s = 5\n" +
                                                  "[[fault]]\nkind = \"spoof\"\nat = 35\nduration = 5\nspeed_mps = 1\n");
  EXPECT_NO_THROW((void)build_config(std::nullopt, {{"scenario", {after}}}));
  const auto apart = write_temp("apart.toml", spoof + "receiver = 0\n" + spoof + "receiver = 1\n");
  EXPECT_NO_THROW((void)build_config(std::nullopt, {{"scenario", {apart}}, {"receivers", {"2"}}, {"output", {"file:/tmp/gpsemu_scn_{i}.nmea"}}}));
}

// What the run knows once it starts (its first epoch, its last one on the run's grid): an at_utc
// outside it, or an at after the last epoch, is refused naming file, line and key.
TEST(Scenario, AFaultOutsideTheRunsOwnEpochsIsRefused) {
  const auto file = write_temp("run.toml", "[[fault]]\nkind = \"outage\"\nat = 9.5\n[[fault]]\nkind = \"outage\"\n"
                                           "at_utc = \"2026-05-01T11:00:00Z\"\nduration = 60\n");
  const Config c = build_config(std::nullopt, {{"scenario", {file}}});
  const UtcNs first = parse_iso8601_utc("2026-05-01T12:00:00Z");
  const auto error_of_run = [&](const RunTimes& run) {
    try {
      check_fault_run_times(c.timeline.faults, run);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of_run({first, true, 10.0, 9.0}),
            "scenario file " + file + ":3: [[fault]]: at: 9.5 s is after the run's last epoch (at 9 s of --duration 10 s): the "
            "fault would never start");
  EXPECT_EQ(error_of_run({first, true, 10.0, std::nullopt}),  // a u-blox's client may ask for a faster rate
            "scenario file " + file + ":6: [[fault]]: at_utc: 2026-05-01T11:00:00.000Z + 60 s is over before the run begins "
            "(its first epoch, now: 2026-05-01T12:00:00.000Z): the fault would never be on; --start-time T runs it at another "
            "time");
  EXPECT_EQ(error_of_run({parse_iso8601_utc("2026-05-01T11:00:30Z"), false, 10.0, 9.5}), "");
}

}  // namespace scenario_test
}  // namespace
}  // namespace gpsemu
