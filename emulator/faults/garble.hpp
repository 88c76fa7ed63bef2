// The `garble` fault on an epoch's bytes, as a bad serial line or a failing UART does it: each
// NMEA sentence and UBX frame is hit with probability `rate`; a hit one has either one bit flipped
// inside its checksummed part (the checksum no longer matches: a parser rejects it) or is cut
// short (the rest of the sentence or frame is lost, its line end too). Bytes between sentences
// and frames are left alone. Deterministic: the same bytes and seed give the same result.
#pragma once

#include <cstdint>
#include <string>

namespace gpsemu::faults {

struct GarbleCounts {
  std::uint64_t units = 0;      ///< sentences and frames seen
  std::uint64_t flipped = 0;    ///< with one bit flipped (bad checksum)
  std::uint64_t truncated = 0;  ///< cut short
};

/// Garbles `bytes` in place: each sentence or frame hit with probability `rate` (0..1), the draws
/// from `seed` (e.g. the run's seed mixed with the epoch's time).
GarbleCounts garble(std::string& bytes, double rate, std::uint64_t seed);

/// A 64-bit mix of two values (splitmix64), for seeds derived from a run's seed and an epoch.
[[nodiscard]] std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b);

}  // namespace gpsemu::faults
