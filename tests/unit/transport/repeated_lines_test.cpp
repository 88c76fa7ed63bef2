// Repeated events of an output go through the one shared limiter (emulator/common/log_limit.hpp), not a
// once-a-second logic of their own (issue 22 point 7): an output whose every write fails, and one
// whose clients' answers find no room, write a line a second each, and the lines account for
// every event — each line stands for itself plus the "N similar lines suppressed" it says — and
// the process count of suppressed lines (the run's summary) grows by the rest. No time is
// asserted: the lines may straddle a second on a loaded machine, the accounting holds whatever
// the timing.
#include <gtest/gtest.h>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "emulator/common/log_limit.hpp"
#include "transport/output.hpp"

namespace gpsemu::transport {
namespace {
namespace repeated_lines_test {

/// Every write fails.
class FailingOutput final : public Output {
 public:
  [[nodiscard]] std::string describe() const override { return "failing"; }
  void feed(std::string_view bytes) { client_wrote(bytes, 1); }

 protected:
  WriteStatus write_bytes(std::string_view, std::string& error_text) override {
    error_text = "disk on fire";
    return WriteStatus::error;
  }
};

/// Answers every byte a client writes with 70 KiB: more than an output keeps for its clients.
class Chatty final : public ClientInput {
 public:
  void client_wrote(std::string_view, ClientId) override {}
  std::string take_reply(ClientId) override { return std::string(70 * 1024, 'x'); }
};

/// Captures the default logger's lines for the test's life.
class CapturedLog {
 public:
  CapturedLog() : previous_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(text_);
    auto logger = std::make_shared<spdlog::logger>("captured", sink);
    logger->set_pattern("%v");
    logger->set_level(spdlog::level::info);
    spdlog::set_default_logger(logger);
  }
  ~CapturedLog() { spdlog::set_default_logger(previous_); }
  [[nodiscard]] std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::logger> previous_;
};

/// The lines holding `needle`, and the events they stand for (each line 1 + its suppressed count).
struct Accounted {
  std::uint64_t lines = 0;
  std::uint64_t events = 0;
};
Accounted account(const std::string& log, const std::string& needle) {
  Accounted a;
  std::istringstream in(log);
  std::string line;
  const std::regex note(R"(\(([0-9]+) similar lines? suppressed\)$)");
  while (std::getline(in, line)) {
    if (line.find(needle) == std::string::npos) continue;
    ++a.lines;
    ++a.events;
    std::smatch m;
    if (std::regex_search(line, m, note)) a.events += std::stoull(m[1]);
  }
  return a;
}

TEST(RepeatedLines, AnOutputsFailedWritesAreOneLineASecondAndAccountForEveryFailure) {
  CapturedLog log;
  FailingOutput out;
  const std::uint64_t suppressed_before = log_lines_suppressed();
  const auto begin = std::chrono::steady_clock::now();
  constexpr std::uint64_t kFailures = 20'000;
  for (std::uint64_t k = 0; k < kFailures; ++k) EXPECT_EQ(out.write_epoch("$GPRMC,x*00\r\n"), WriteStatus::error);
  const auto seconds_taken = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  // One more after a second: its line reports what the flood's window suppressed.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  EXPECT_EQ(out.write_epoch("$GPRMC,x*00\r\n"), WriteStatus::error);
  EXPECT_EQ(out.stats().epochs_failed, kFailures + 1);

  const std::string text = log.text();
  const Accounted a = account(text, "failing: epoch not written (disk on fire)");
  EXPECT_LE(a.lines, 2u + static_cast<std::uint64_t>(seconds_taken)) << text;
  EXPECT_GE(a.lines, 2u) << text;
  EXPECT_EQ(a.events, kFailures + 1) << "every failure is a line or counted in the next line\n" << text;
  EXPECT_EQ(log_lines_suppressed() - suppressed_before, kFailures + 1 - a.lines);
}

TEST(RepeatedLines, AnswersDroppedForWantOfRoomAreOneLineASecond) {
  CapturedLog log;
  FailingOutput out;
  Chatty chatty;
  out.set_client_input(&chatty);
  const auto begin = std::chrono::steady_clock::now();
  constexpr std::uint64_t kReads = 5'000;
  for (std::uint64_t k = 0; k < kReads; ++k) out.feed("?");  // each answer is over the 64 KiB kept
  const auto seconds_taken = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  EXPECT_EQ(out.stats().replies_dropped, kReads);
  const std::string text = log.text();
  const Accounted a = account(text, "batch(es) of answers to clients dropped whole");
  EXPECT_GE(a.lines, 1u) << text;
  EXPECT_LE(a.lines, 2u + static_cast<std::uint64_t>(seconds_taken)) << text;
  // Each line counts the batches since the one before, so the lines' counts add up to those
  // reported; the last line's may be followed by drops not yet reported.
  std::uint64_t batches = 0;
  std::istringstream in(text);
  std::string line;
  const std::regex count(R"(failing: ([0-9]+) batch\(es\))");
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, count)) batches += std::stoull(m[1]);
  }
  EXPECT_GE(batches, 1u);
  EXPECT_LE(batches, kReads);
}

TEST(RepeatedLines, AWindowLongerThanASecondLetsOneLineThroughEachWindow) {
  LogLimit limit(1, std::chrono::seconds(10));
  const LogLimit::Clock::time_point t0{std::chrono::seconds(50)};
  EXPECT_TRUE(limit.admit(t0));
  EXPECT_FALSE(limit.admit(t0 + std::chrono::seconds(1)));
  EXPECT_FALSE(limit.admit(t0 + std::chrono::milliseconds(9999)));
  EXPECT_TRUE(limit.admit(t0 + std::chrono::seconds(10)));
  EXPECT_EQ(limit.take_suppressed(), 2u);
}

}  // namespace repeated_lines_test
}  // namespace
}  // namespace gpsemu::transport
