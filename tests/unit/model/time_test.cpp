// The UTC epoch grid and ISO 8601 parsing.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "emulator/model/time.hpp"

namespace gpsemu {
namespace {
namespace time_test {

using namespace std::chrono;

TEST(EpochGrid, TenHertzEpochsFallOnTenthsOfASecond) {
  const EpochGrid grid(10.0);
  const UtcNs t0 = parse_iso8601_utc("2024-05-01T12:00:00Z");
  const auto k = grid.index_at_or_after(t0 + milliseconds(1));
  EXPECT_EQ(grid.time_of(k), t0 + milliseconds(100));
  EXPECT_EQ(grid.time_of(k + 9), t0 + seconds(1));
  EXPECT_EQ(grid.time_of(k + 1) - grid.time_of(k), milliseconds(100));
}

TEST(EpochGrid, OneHertzEpochsAreWholeSeconds) {
  const EpochGrid grid(1.0);
  const UtcNs t = parse_iso8601_utc("2024-05-01T12:00:00.2Z");
  EXPECT_EQ(grid.time_of(grid.index_at_or_after(t)), parse_iso8601_utc("2024-05-01T12:00:01Z"));
  EXPECT_EQ(grid.time_of(grid.index_at_or_after(parse_iso8601_utc("2024-05-01T12:00:01Z"))),
            parse_iso8601_utc("2024-05-01T12:00:01Z"));
}

TEST(EpochGrid, ThreeHertzHasNoRepeatedOrDriftingEpochs) {
  const EpochGrid grid(3.0);
  const auto k = grid.index_at_or_after(parse_iso8601_utc("2024-05-01T00:00:00Z"));
  for (int i = 0; i < 300; ++i) EXPECT_LT(grid.time_of(k + i), grid.time_of(k + i + 1));
  EXPECT_EQ(grid.time_of(k + 300), parse_iso8601_utc("2024-05-01T00:01:40Z"));
}

TEST(EpochGrid, SubHertzRatesUseWholeSecondPeriods) {
  const EpochGrid grid(0.2);
  const auto k = grid.index_at_or_after(parse_iso8601_utc("2024-05-01T00:00:01Z"));
  EXPECT_EQ(grid.time_of(k), parse_iso8601_utc("2024-05-01T00:00:05Z"));
  EXPECT_EQ(grid.time_of(k + 1), parse_iso8601_utc("2024-05-01T00:00:10Z"));
}

TEST(EpochGrid, RejectsRatesOffTheGrid) {
  EXPECT_THROW(EpochGrid(0.0), std::invalid_argument);
  EXPECT_THROW(EpochGrid(2.5), std::invalid_argument);
  EXPECT_THROW(EpochGrid(0.3), std::invalid_argument);
  EXPECT_THROW(EpochGrid(51.0), std::invalid_argument);
}

TEST(Iso8601, ParsesAndFormatsUtc) {
  const UtcNs t = parse_iso8601_utc("2024-02-29T23:59:59.75Z");
  EXPECT_EQ(format_iso8601_utc(t), "2024-02-29T23:59:59.750Z");
  EXPECT_EQ(parse_iso8601_utc("2024-02-29 23:59:59"), parse_iso8601_utc("2024-02-29T23:59:59Z"));
  EXPECT_EQ(format_iso8601_utc(t + milliseconds(250)), "2024-03-01T00:00:00.000Z");
}

TEST(Iso8601, RejectsMalformedTimesWithTheTextInTheMessage) {
  for (const char* bad : {"2024-02-30T00:00:00Z", "2024-13-01T00:00:00Z", "yesterday",
                          "2024-01-01T25:00:00Z", "2024-01-01T00:00:00+02:00", "2024-01-01T00:00:00."}) {
    try {
      (void)parse_iso8601_utc(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

// Found by trajectory_csv_fuzz: year 1173 overflowed the 64-bit nanosecond count (undefined
// behaviour). Years outside what UtcNs holds, with room for decades of durations, are refused.
TEST(Iso8601, YearsOutsideTheRangeAreRefused) {
  EXPECT_EQ(format_iso8601_utc(parse_iso8601_utc("1970-01-01T00:00:00Z")), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(format_iso8601_utc(parse_iso8601_utc("2199-12-31T23:59:59.999Z")), "2199-12-31T23:59:59.999Z");
  for (const char* bad : {"1173-05-01T12:00:00Z", "1969-12-31T23:59:59Z", "2200-01-01T00:00:00Z", "9999-12-31T00:00:00Z",
                          "0000-01-01T00:00:00Z"}) {
    try {
      (void)parse_iso8601_utc(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), fmt::format("'{}': the year must be 1970..2199", bad));
    }
  }
}

}  // namespace time_test
}  // namespace
}  // namespace gpsemu
