#include "emulator/common/log_limit.hpp"

#include <atomic>

#include <fmt/format.h>

namespace gpsemu {
namespace {

std::atomic<std::uint64_t> g_suppressed{0};

}  // namespace

std::uint64_t log_lines_suppressed() { return g_suppressed.load(std::memory_order_relaxed); }

bool LogLimit::admit(Clock::time_point now) {
  if (!started_ || now - window_start_ >= window_ || now < window_start_) {
    started_ = true;
    window_start_ = now;
    in_window_ = 0;
  }
  if (in_window_ < per_second_) {
    ++in_window_;
    return true;
  }
  ++suppressed_;
  ++suppressed_total_;
  g_suppressed.fetch_add(1, std::memory_order_relaxed);
  return false;
}

std::uint64_t LogLimit::take_suppressed() {
  const std::uint64_t n = suppressed_;
  suppressed_ = 0;
  return n;
}

std::string suppressed_note(std::uint64_t suppressed) {
  if (suppressed == 0) return {};
  return fmt::format(" ({} similar line{} suppressed)", suppressed, suppressed == 1 ? "" : "s");
}

}  // namespace gpsemu
