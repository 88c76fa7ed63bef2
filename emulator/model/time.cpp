#include "emulator/model/time.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace gpsemu {
namespace {

int read_int(std::string_view text, std::size_t pos, std::size_t len, std::string_view whole) {
  int value = 0;
  if (pos + len > text.size()) throw std::invalid_argument(fmt::format("'{}' is too short", whole));
  auto [ptr, ec] = std::from_chars(text.data() + pos, text.data() + pos + len, value);
  if (ec != std::errc{} || ptr != text.data() + pos + len) {
    throw std::invalid_argument(fmt::format("'{}' is not of the form YYYY-MM-DDThh:mm:ss[.fff]Z", whole));
  }
  return value;
}

void expect(std::string_view text, std::size_t pos, std::string_view chars, std::string_view whole) {
  if (pos >= text.size() || chars.find(text[pos]) == std::string_view::npos) {
    throw std::invalid_argument(fmt::format("'{}' is not of the form YYYY-MM-DDThh:mm:ss[.fff]Z", whole));
  }
}

}  // namespace

UtcNs parse_iso8601_utc(std::string_view text, UtcSuffix suffix) {
  using namespace std::chrono;
  const std::string_view whole = text;
  const int y = read_int(text, 0, 4, whole);
  expect(text, 4, "-", whole);
  const int mo = read_int(text, 5, 2, whole);
  expect(text, 7, "-", whole);
  const int d = read_int(text, 8, 2, whole);
  expect(text, 10, "T ", whole);
  const int hh = read_int(text, 11, 2, whole);
  expect(text, 13, ":", whole);
  const int mm = read_int(text, 14, 2, whole);
  expect(text, 16, ":", whole);
  const int ss = read_int(text, 17, 2, whole);
  std::size_t pos = 19;
  std::int64_t frac_ns = 0;
  if (pos < text.size() && text[pos] == '.') {
    ++pos;
    std::int64_t scale = 100'000'000;
    const std::size_t start = pos;
    while (pos < text.size() && text[pos] >= '0' && text[pos] <= '9') {
      frac_ns += (text[pos] - '0') * scale;
      scale /= 10;
      ++pos;
    }
    if (pos == start) throw std::invalid_argument(fmt::format("'{}' has an empty fraction of a second", whole));
  }
  const std::string_view rest = text.substr(pos);
  if (!(rest.empty() || rest == "Z" || rest == "z" || rest == "+00:00")) {
    throw std::invalid_argument(fmt::format("'{}': only UTC times are accepted (end with Z)", whole));
  }
  if (rest.empty() && suffix == UtcSuffix::required) {
    throw std::invalid_argument(fmt::format("'{}': end the time with Z to say it is UTC, e.g. {}Z (local times and "
                                            "offsets are not accepted)", whole, whole));
  }
  const year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)}, day{static_cast<unsigned>(d)}};
  if (!ymd.ok() || hh > 23 || mm > 59 || ss > 59) {
    throw std::invalid_argument(fmt::format("'{}' is not a valid date and time", whole));
  }
  // UtcNs (64-bit nanoseconds) holds 1677..2262; later code adds durations of up to decades.
  constexpr int kMinYear = 1970, kMaxYear = 2199;
  if (y < kMinYear || y > kMaxYear) {
    throw std::invalid_argument(fmt::format("'{}': the year must be {}..{}", whole, kMinYear, kMaxYear));
  }
  return UtcNs{sys_days{ymd}} + hours{hh} + minutes{mm} + seconds{ss} + nanoseconds{frac_ns};
}

std::string format_iso8601_utc(UtcNs time) {
  using namespace std::chrono;
  const auto day = floor<days>(time);
  const year_month_day ymd{day};
  const hh_mm_ss hms{floor<milliseconds>(time - day)};
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", static_cast<int>(ymd.year()),
                     static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()),
                     hms.hours().count(), hms.minutes().count(), hms.seconds().count(),
                     hms.subseconds().count());
}

EpochGrid::EpochGrid(double rate_hz) : rate_hz_(rate_hz) {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0) {
    throw std::invalid_argument("rate must be a positive number of epochs per second");
  }
  if (rate_hz >= 1.0) {
    if (rate_hz != std::floor(rate_hz) || rate_hz > 50.0) {
      throw std::invalid_argument(fmt::format(
          "rate {} Hz: use a whole number of epochs per second from 1 to 50 (or 0.5, 0.25, 0.2, 0.1)",
          rate_hz));
    }
    per_second_ = static_cast<std::int64_t>(rate_hz);
  } else {
    const double period = 1.0 / rate_hz;
    if (std::abs(period - std::round(period)) > 1e-9 || period > 10.0) {
      throw std::invalid_argument(fmt::format(
          "rate {} Hz: below 1 Hz the period must be a whole number of seconds up to 10 (0.5, 0.25, 0.2, 0.1)",
          rate_hz));
    }
    period_s_ = static_cast<std::int64_t>(std::llround(period));
  }
}

std::int64_t EpochGrid::index_at_or_after(UtcNs t) const {
  const std::int64_t ns = t.time_since_epoch().count();
  const std::int64_t sec = ns >= 0 ? ns / 1'000'000'000 : -((-ns + 999'999'999) / 1'000'000'000);
  if (per_second_ > 0) {
    std::int64_t index = sec * per_second_;
    while (time_of(index) < t) ++index;  // at most per_second_ steps
    return index;
  }
  std::int64_t index = sec / period_s_ - 1;
  while (time_of(index) < t) ++index;
  return index;
}

UtcNs EpochGrid::time_of(std::int64_t index) const {
  using std::chrono::nanoseconds;
  if (per_second_ > 0) {
    std::int64_t sec = index / per_second_;
    std::int64_t j = index % per_second_;
    if (j < 0) {
      j += per_second_;
      --sec;
    }
    // Rounded to the nearest nanosecond: 3 Hz gives .000, .333333333, .666666667.
    const std::int64_t frac = (j * 1'000'000'000 + per_second_ / 2) / per_second_;
    return UtcNs{nanoseconds{sec * 1'000'000'000 + frac}};
  }
  return UtcNs{nanoseconds{index * period_s_ * 1'000'000'000}};
}

std::chrono::nanoseconds EpochGrid::nominal_period() const {
  if (per_second_ > 0) return std::chrono::nanoseconds{1'000'000'000 / per_second_};
  return std::chrono::seconds{period_s_};
}

}  // namespace gpsemu
