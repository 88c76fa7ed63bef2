// `gpsemu replay --speed N` on the real receivers' logs (tests/data/real). Every epoch comes
// out, in order, content unchanged (the output is exactly the log's valid sentences, found here
// by a scan of our own), each epoch's spacing is the log's spacing / N (the logs go at speed 40,
// 25 ms apart at 1 Hz, to keep the suite short: the 11-minute F9P log in 16 s). The
// spacing figures are reported (mean, 95th percentile, worst, share within +-5 ms); asserted are the
// median spacing error and the span of the arrivals (the machine running the tests may be shared
// and busy: the worst spacing is a measurement, not a test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "emulator/replay/replay_log.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::replay {
namespace {
namespace replay_real_logs_test {

namespace fs = std::filesystem;
using namespace std::chrono;

const std::string kDir = std::string(GPSEMU_SOURCE_DIR) + "/tests/data/real";

using test::read_file;

/// The log's valid sentences with their line endings, by a scan independent of the replay's
/// reader: '$', printable characters without another '$', '*hh' matching, then CR/LF.
std::string valid_sentences(const std::string& log) {
  std::string out;
  std::size_t i = 0;
  while ((i = log.find('$', i)) != std::string::npos) {
    if (i > 0 && log.rfind('\n', i) != std::string::npos && log[log.rfind('\n', i) + 1] == '#') {
      i = log.find('\n', i);  // inside a comment line
      continue;
    }
    std::size_t j = i + 1;
    while (j < log.size() && log[j] >= 0x20 && log[j] <= 0x7e && log[j] != '$') ++j;
    const bool ended = j == log.size() || log[j] == '\r' || log[j] == '\n';
    const std::string body = log.substr(i, j - i);
    const auto star = body.rfind('*');
    std::string hex = star == std::string::npos ? "" : body.substr(star + 1);
    for (auto& c : hex) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (ended && star != std::string::npos && star + 3 == body.size() && body.size() <= 120 &&
        fmt::format("{:02X}", nmea::checksum(std::string_view(body).substr(1, star - 1))) == hex) {
      std::size_t end = j;  // the line ending as recorded: CR LF, CR or LF
      if (end < log.size() && log[end] == '\r' && end + 1 < log.size() && log[end + 1] == '\n') {
        end += 2;
      } else if (end < log.size()) {
        end += 1;
      }
      out += log.substr(i, end - i);
      i = end;
      continue;
    }
    i = j;
  }
  return out;
}

void replay_real_log(const std::string& name, std::size_t expected_epochs, double speed = 10.0) {
  const fs::path path = fs::path(kDir) / name;
  ASSERT_TRUE(fs::exists(path)) << "real receiver log " << path << " is part of the repository";
  const std::string log_bytes = read_file(path);
  const ReplayLog log = parse_replay_log(log_bytes);
  ASSERT_EQ(log.epochs.size(), expected_epochs);
  std::string expected_all;
  for (const auto& e : log.epochs) expected_all += e.bytes;
  ASSERT_EQ(expected_all, valid_sentences(log_bytes)) << "the epochs hold exactly the log's valid sentences";
  const double log_span_s = duration<double>(log.epochs.back().log_time - log.epochs.front().log_time).count();

  std::vector<std::string> argv{GPSEMU_BINARY, "replay", path.string(), "--speed", fmt::format("{}", speed), "--output",
                                "stdout"};
  // GPSEMU_TEST_REPLAY_ARGS (space-separated) adds options, e.g. "--realtime-priority 10 --timer-slack 1".
  if (const char* extra = std::getenv("GPSEMU_TEST_REPLAY_ARGS")) {
    std::istringstream words(extra);
    for (std::string w; words >> w;) argv.push_back(w);
  }
  test::Process gpsemu(argv);
  ASSERT_EQ(gpsemu.wait(milliseconds(static_cast<int>(log_span_s * 1000.0 / speed) + 30'000)), 0) << gpsemu.stderr_text();
  std::string all;
  std::vector<std::pair<std::size_t, double>> starts;
  for (const auto& c : gpsemu.chunks()) {
    starts.emplace_back(all.size(), c.read_s);
    all += c.bytes;
  }
  ASSERT_EQ(all.size(), expected_all.size());
  ASSERT_TRUE(all == expected_all) << "content or order changed";

  // Each epoch's arrival (when it started a read) against the previous one's.
  std::vector<double> errors_ms;
  std::size_t offset = 0, chunk = 0, merged = 0;
  double previous_s = std::nan("");
  for (std::size_t i = 0; i < log.epochs.size(); ++i) {
    while (chunk < starts.size() && starts[chunk].first < offset) ++chunk;
    const bool starts_read = chunk < starts.size() && starts[chunk].first == offset;
    const double at = starts_read ? starts[chunk].second : std::nan("");
    if (!starts_read) ++merged;
    if (i > 0 && !std::isnan(at) && !std::isnan(previous_s)) {
      const double expected_ms =
          std::max(0.0, duration<double, std::milli>(log.epochs[i].log_time - log.epochs[i - 1].log_time).count() / speed);
      errors_ms.push_back(1000.0 * (at - previous_s) - expected_ms);
    }
    previous_s = at;
    offset += log.epochs[i].bytes.size();
  }
  ASSERT_GE(errors_ms.size(), log.epochs.size() * 9 / 10) << merged << " epochs did not start a read";
  // Also against the ideal schedule (first arrival + log time / 10), epochs sent in order only.
  double worst_schedule_ms = 0.0;
  {
    std::size_t off = 0, c = 0;
    std::optional<double> first_at;
    nanoseconds latest = log.epochs.front().log_time;
    for (const auto& e : log.epochs) {
      while (c < starts.size() && starts[c].first < off) ++c;
      if (c < starts.size() && starts[c].first == off && e.log_time >= latest) {
        if (!first_at) first_at = starts[c].second;
        const double ideal = *first_at + duration<double>(e.log_time - log.epochs.front().log_time).count() / speed;
        worst_schedule_ms = std::max(worst_schedule_ms, std::abs(1000.0 * (starts[c].second - ideal)));
      }
      latest = std::max(latest, e.log_time);
      off += e.bytes.size();
    }
  }
  const auto delay_at = gpsemu.stderr_text().find("worst send delay");
  const std::string sender_side =
      delay_at == std::string::npos ? "" : gpsemu.stderr_text().substr(delay_at, gpsemu.stderr_text().find('\n', delay_at) - delay_at);
  std::vector<double> abs_ms;
  double sum = 0.0;
  for (const double e : errors_ms) {
    abs_ms.push_back(std::abs(e));
    sum += e;
  }
  std::sort(abs_ms.begin(), abs_ms.end());
  const double p95 = abs_ms[abs_ms.size() * 95 / 100], worst = abs_ms.back();
  const auto within5 = std::count_if(abs_ms.begin(), abs_ms.end(), [](double e) { return e <= 5.0; });
  const std::string figures = fmt::format(
      "{}: {} epochs, {} spacings measured: mean error {:+.3f} ms, 95th percentile |error| {:.3f} ms, worst {:.3f} ms, "
      "{:.1f}% within +-5 ms; worst |arrival - ideal schedule| {:.3f} ms; replay's own {}", name, log.epochs.size(),
      errors_ms.size(), sum / static_cast<double>(errors_ms.size()), p95, worst,
      100.0 * static_cast<double>(within5) / static_cast<double>(abs_ms.size()), worst_schedule_ms, sender_side);
  std::printf("[ info ] %s\n", figures.c_str());
  ::testing::Test::RecordProperty("spacing", figures);
  // Pacing, not timing precision (that is measured by tools/measure-timing, figures in
  // docs/performance.md): the median spacing error is small, and the arrivals span the log's span
  // / speed (a replay sending everything at once, or at speed 1, fails both). The worst spacing is
  // reported, not asserted: one late wake-up on a shared machine says nothing about the replay.
  const double median = abs_ms[abs_ms.size() / 2];
  EXPECT_LT(median, 5.0) << figures;
  const double span_s = starts.back().second - starts.front().second;
  EXPECT_NEAR(span_s, log_span_s / speed, 0.01 * log_span_s + 0.05) << figures;
}

TEST(ReplayRealLogs, QuectelL76kAtSpeed40EveryEpochUnchangedAndOnTime) {
  replay_real_log("quectel-l76k-dual.log", 130, 40.0);
}
TEST(ReplayRealLogs, TelitHe910AtSpeed40EveryEpochUnchangedAndOnTime) { replay_real_log("telit-he910.log", 224, 40.0); }
TEST(ReplayRealLogs, UbloxZedF9pAtSpeed40EveryEpochUnchangedAndOnTime) {
  replay_real_log("ublox-zed-f9p_hpg1.11.log", 655, 40.0);
}

}  // namespace replay_real_logs_test
}  // namespace
}  // namespace gpsemu::replay
