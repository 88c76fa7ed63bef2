// A recorded NMEA log cut into the receiver's epochs, for `gpsemu replay` (replayer.hpp).
// Pure: bytes in, epochs and counts out; no I/O except read_replay_log(), no clocks.
//
// - The byte stream goes through nmea::StreamReader: binary protocols (UBX, CASIC...), garbage,
//   '#' comment lines (gpsd log headers, `--tee` files' "# sent" lines), malformed sentences and
//   bad checksums are skipped and counted. Each good sentence keeps its recorded bytes, from '$'
//   to its line ending (CR LF, LF or CR, as recorded).
// - An epoch is a run of consecutive sentences sharing a time field (GGA, RMC, GLL, ZDA, GST, GNS,
//   GBS, GRS carry one). Sentences without a time field (GSA, GSV, VTG, TXT, proprietary...)
//   belong to the epoch they sit in; at the start of the log, to the first epoch. An epoch of more
//   than kMaxEpochSentences sentences or kMaxEpochBytes bytes (a log of one repeated time) is
//   oversized: skipped whole and counted. A sentence whose
//   time field is empty (no fix, no time yet) stays in the current epoch unless its address
//   (e.g. GPGGA) is already there: then it starts a new epoch without a time.
// - The log's timeline: times of day in order, a day added when the time goes back by more than
//   12 h (midnight rollover). A smaller step back is kept as recorded (sent right after the
//   previous epoch) and counted. Epochs without a time are placed one nominal period (the median
//   spacing of the first kPeriodSpacings spacings of timed epochs, 1 s when there is none) after
//   the previous epoch, or before the first timed one.
// The log is read as a stream with a bounded look-ahead (log_stream.hpp); parse_replay_log() runs
// the same reader over a log in memory and keeps every epoch (tests, fuzzing).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/config/spec/replay_options.hpp"
#include "emulator/model/time.hpp"
#include "nmea/parse.hpp"

namespace gpsemu::replay {

/// Largest epoch replayed: a real receiver's is a few dozen sentences and a few KiB.
inline constexpr std::uint64_t kMaxEpochSentences = 1000;
inline constexpr std::size_t kMaxEpochBytes = 128 * 1024;

/// One good sentence of the log.
struct LogSentence {
  std::string raw;        ///< as recorded: '$' to the checksum digits, plus its line ending
  nmea::Sentence parsed;  ///< its fields (for retiming)
  /// Its time field (since UTC midnight), when its type has one and it holds a valid time.
  std::optional<std::chrono::nanoseconds> time_of_day;
};

struct LogEpoch {
  std::vector<LogSentence> sentences;
  std::string bytes;  ///< the sentences' raw bytes, in order: what is sent
  std::optional<std::chrono::nanoseconds> time_of_day;  ///< the shared time field; none for a no-time epoch
  std::chrono::nanoseconds log_time{0};  ///< on the log's timeline (day * 24 h + time of day)
};

/// What was skipped and what the timeline looks like.
struct LogCounts {
  nmea::StreamStats stream;              ///< sentences ok, bad checksums, malformed, garbage, comments
  std::uint64_t bad_time_fields = 0;     ///< time fields that are not hhmmss[.s...] (their sentence kept, untimed)
  std::uint64_t untimed_epochs = 0;      ///< epochs without any time field
  std::uint64_t gaps = 0;                ///< spacings over 1.5 nominal periods (missing epochs)
  std::chrono::nanoseconds longest_gap{0};
  std::uint64_t steps_back = 0;          ///< times that went back by 12 h or less
  std::uint64_t rollovers = 0;           ///< midnight rollovers
  std::uint64_t oversized_epochs = 0;    ///< epochs over kMaxEpochSentences/kMaxEpochBytes, skipped
  std::uint64_t oversized_sentences = 0; ///< the sentences they held
};

struct ReplayLog {
  std::vector<LogEpoch> epochs;
  LogCounts counts;
  std::chrono::nanoseconds period{std::chrono::seconds(1)};  ///< nominal epoch spacing
};

/// Cuts `bytes` (a whole log) into epochs: every epoch LogStream hands out, kept.
[[nodiscard]] ReplayLog parse_replay_log(std::string_view bytes);

/// Epochs first..last (both included) of a log.
struct EpochRange {
  std::size_t first = 0;
  std::size_t last = 0;
};

/// The epochs --from/--to select (epoch_range.hpp's RangeCursor over the epochs): a time of day is
/// the first epoch at or after it (--from), the last at or before it (--to), both on the log's
/// timeline (across midnight too); an index is that epoch. Throws std::invalid_argument naming the option when the range is empty or an
/// index is past the end.
[[nodiscard]] EpochRange select_range(const ReplayLog& log, const std::optional<LogPosition>& from,
                                      const std::optional<LogPosition>& to);

/// The epoch's bytes with every time field set to `time`'s time of day (as many decimals as
/// recorded, rounded) and every date field (RMC ddmmyy, ZDA dd,mm,yyyy) to its date; empty
/// fields stay empty; checksums recomputed (upper-case hex); line endings as recorded.
[[nodiscard]] std::string retime_epoch(const LogEpoch& epoch, UtcNs time);

/// The index of the time field of a sentence type (GGA 0, GLL 4, ...), or nothing.
[[nodiscard]] std::optional<std::size_t> time_field_index(const nmea::Sentence& sentence);

/// "hhmmss", "hhmmss.s..." as time since midnight; nothing when malformed.
[[nodiscard]] std::optional<std::chrono::nanoseconds> parse_time_of_day(std::string_view field);

}  // namespace gpsemu::replay
