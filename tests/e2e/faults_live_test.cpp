// Live control over TCP while gpsemu runs in real time at 10 Hz: each request is answered before
// the next epoch (its answer names the epoch it came after) and takes effect exactly at the next
// epoch (the --tee file records the epoch each event applied at, the NMEA shows it there); no
// epoch is late. The --tee file then replays the session: `--scenario TEE --fast` with the same
// seed and start time writes the same bytes.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/model/time.hpp"
#include "emulator/pipeline/control_socket.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace faults_live_test {

using namespace std::chrono;
using nlohmann::json;

constexpr const char* kStart = "2030-01-01T00:00:00Z";

/// The GGA fix quality of each epoch in `nmea`, by ms after kStart.
std::map<std::int64_t, int> qualities(const std::string& nmea) {
  std::map<std::int64_t, int> out;
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(nmea)) {
    if (s.type != "GGA") continue;
    const auto gga = nmea::parse_gga(s);
    if (gga.ok() && gga->time_of_day) out[gga->time_of_day->count()] = static_cast<int>(gga->quality);
  }
  return out;
}

/// A --tee file's "# fault +S ..." lines: S in ms, and the request.
std::vector<std::pair<std::int64_t, json>> tee_events(const std::string& tee) {
  std::vector<std::pair<std::int64_t, json>> out;
  const std::regex line(R"(# fault \+([0-9.]+) \S+ (\{.*\}))");
  std::smatch m;
  std::string::const_iterator from = tee.begin();
  while (std::regex_search(from, tee.end(), m, line)) {
    out.emplace_back(std::llround(std::stod(m[1].str()) * 1000.0), json::parse(m[2].str()));
    from = m[0].second;
  }
  return out;
}

/// The tee file without its comment lines: the bytes sent.
std::string sent_bytes(const std::string& tee) {
  std::string out;
  std::size_t at = 0;
  while (at < tee.size()) {
    std::size_t nl = tee.find('\n', at);
    nl = nl == std::string::npos ? tee.size() : nl + 1;
    if (tee.compare(at, 2, "# ") != 0) out.append(tee, at, nl - at);
    at = nl;
  }
  return out;
}

TEST(FaultsLive, TcpRequestsAt10HzApplyAtTheNextEpochAndTheTeeReplaysTheSession) {
  const auto dir = test::scratch_dir("faults", "live");
  const std::string out = (dir / "out.nmea").string(), tee = (dir / "session.tee").string();
  test::Process gpsemu({GPSEMU_BINARY, "--rate", "10", "--duration", "6", "--seed", "31", "--start-time", kStart,
                        "--output", "file:" + out, "--tee", tee, "--control", "tcp:127.0.0.1:0", "--log-level", "info"});
  const std::optional<std::string> started = gpsemu.wait_for_stderr("control socket tcp:", seconds(20));
  ASSERT_TRUE(started) << gpsemu.stderr_text();
  std::smatch m;
  ASSERT_TRUE(std::regex_search(*started, m, std::regex(R"(control socket (tcp:127\.0\.0\.1:[0-9]+))"))) << *started;
  const std::string socket = m[1].str();

  // Requests spread over the run, each answered before the next epoch.
  const std::vector<std::string> requests{
      R"({"fault":"outage","duration":0.5})",
      R"({"fault":"jam","db":40})",
      R"({"clear":"jam"})",
      R"({"fault":"fix-quality","quality":"rtk-fixed"})",
      R"({"clear":"all"})",
  };
  std::vector<double> after_epoch_s;
  double worst_answer_ms = 0.0;
  for (const std::string& request : requests) {
    const auto pause_until = steady_clock::now() + milliseconds(700);
    while (steady_clock::now() < pause_until) gpsemu.pump(milliseconds(50));  // its log flows meanwhile
    const auto asked = steady_clock::now();
    const json answer = json::parse(control_request(socket, request, seconds(2)));
    worst_answer_ms = std::max(worst_answer_ms, duration<double, std::milli>(steady_clock::now() - asked).count());
    ASSERT_NE(answer["class"], "ERROR") << answer.dump();
    ASSERT_TRUE(answer["after_epoch_s"].is_number()) << answer.dump();
    after_epoch_s.push_back(answer["after_epoch_s"].get<double>());
  }
  const json status = json::parse(control_request(socket, R"({"status":true})", seconds(2)));
  EXPECT_EQ(status["class"], "STATUS");
  std::cout << fmt::format("5 requests over TCP at 10 Hz: the slowest answer took {:.1f} ms (connect included)\n",
                           worst_answer_ms);

  ASSERT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  const std::string err = gpsemu.stderr_text();
  EXPECT_TRUE(test::contains(err, " 0 late epochs skipped")) << err;

  // Each event applied at the epoch after the one its answer named.
  const std::string tee_text = test::read_file(tee);
  const auto events = tee_events(tee_text);
  ASSERT_EQ(events.size(), requests.size()) << tee_text.substr(0, 2000);
  for (std::size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].first, std::llround(after_epoch_s[i] * 1000.0) + 100) << requests[i];
    EXPECT_EQ(events[i].second["receiver"], 0);
  }
  EXPECT_EQ(events[0].second["fault"], "outage");
  EXPECT_EQ(events[2].second["clear"], "jam");

  // The NMEA shows them at those epochs: no fix for exactly 5 epochs from the outage's, none from
  // the jam's to the clear's, rtk-fixed (4) from its epoch to the clear of all.
  const std::map<std::int64_t, int> q = qualities(test::read_file(out));
  ASSERT_EQ(q.size(), 60u);
  const std::int64_t outage = events[0].first, jam = events[1].first, unjam = events[2].first, rtk = events[3].first,
                     clear = events[4].first;
  for (const auto& [ms, quality] : q) {
    const bool lost = (ms >= outage && ms < outage + 500) || (ms >= jam && ms < unjam);
    const int expected = lost ? 0 : (ms >= rtk && ms < clear) ? 4 : 1;
    EXPECT_EQ(quality, expected) << "epoch +" << ms << " ms";
  }

  // The session again from its tee file, without anyone at the socket: the same bytes.
  const test::Result replay = test::run({GPSEMU_BINARY, "--fast", "--rate", "10", "--duration", "6", "--seed", "31",
                                         "--start-time", kStart, "--output", "stdout", "--scenario", tee});
  ASSERT_EQ(replay.status, 0) << replay.err;
  EXPECT_EQ(replay.out.size(), sent_bytes(tee_text).size());
  EXPECT_TRUE(replay.out == sent_bytes(tee_text)) << "the replayed session differs from the live one";
  EXPECT_TRUE(replay.out == test::read_file(out));
  std::filesystem::remove_all(dir);
}

}  // namespace faults_live_test
}  // namespace
}  // namespace gpsemu
