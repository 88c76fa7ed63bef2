#include "emulator/faults/garble.hpp"

#include "emulator/model/noise/splitmix.hpp"

#include <cstddef>
#include <string_view>
#include <vector>

namespace gpsemu::faults {
namespace {

/// The shared SplitMix64 (model/noise/splitmix.hpp): the same draws on every platform.
struct Draws : noise::SplitMix64 {
  explicit Draws(std::uint64_t seed) : noise::SplitMix64{seed} {}
  /// Uniform in [0, n), n > 0.
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
};

/// A sentence or frame: [begin, end) of the bytes, and the part a bit flip breaks the checksum of.
struct Unit {
  std::size_t begin, end;
  std::size_t flip_begin, flip_end;
};

std::vector<Unit> units_of(std::string_view b) {
  std::vector<Unit> out;
  std::size_t i = 0;
  while (i < b.size()) {
    const auto c = static_cast<unsigned char>(b[i]);
    if (c == '$' || c == '!') {
      std::size_t end = b.find('\n', i);
      end = end == std::string_view::npos ? b.size() : end + 1;
      const std::size_t star = b.find('*', i);
      // Between the start character and '*' (the checksummed part); none: the body.
      const std::size_t flip_end = star != std::string_view::npos && star < end ? star : end;
      if (flip_end > i + 1) out.push_back({i, end, i + 1, flip_end});
      i = end;
    } else if (c == 0xB5 && i + 1 < b.size() && static_cast<unsigned char>(b[i + 1]) == 0x62 && i + 6 <= b.size()) {
      const std::size_t len = static_cast<unsigned char>(b[i + 4]) | (static_cast<std::size_t>(static_cast<unsigned char>(b[i + 5])) << 8);
      const std::size_t end = i + 8 + len;
      if (end > b.size()) break;  // not a whole frame: left alone
      // The payload (a bit flipped there breaks the Fletcher checksum); empty: class and id.
      out.push_back({i, end, len ? i + 6 : i + 2, len ? i + 6 + len : i + 4});
      i = end;
    } else {
      ++i;
    }
  }
  return out;
}

}  // namespace

std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b) {
  Draws d{a ^ (b * 0x9e3779b97f4a7c15ULL)};
  return d.next();
}

GarbleCounts garble(std::string& bytes, double rate, std::uint64_t seed) {
  GarbleCounts counts;
  if (bytes.empty()) return counts;
  Draws draws{seed};
  const std::vector<Unit> units = units_of(bytes);
  counts.units = units.size();
  std::string out;
  out.reserve(bytes.size());
  std::size_t copied = 0;  // bytes before this were handled
  for (const Unit& u : units) {
    out.append(bytes, copied, u.begin - copied);
    copied = u.end;
    const bool hit = draws.unit() < rate;
    const bool cut = (draws.next() & 1U) != 0;
    if (!hit) {
      out.append(bytes, u.begin, u.end - u.begin);
    } else if (cut) {
      // Cut inside its checksummed part: at least its first byte stays, and never only its line
      // end or checksum goes (a sentence without its LF still ends at its CR, and parses).
      const std::size_t keep = 1 + draws.below(u.flip_end - u.begin - 1);
      out.append(bytes, u.begin, keep);
      ++counts.truncated;
    } else {
      const std::size_t at = u.flip_begin + draws.below(u.flip_end - u.flip_begin);
      const std::size_t bit = draws.below(7);  // one of the low 7 bits: text stays 7-bit
      out.append(bytes, u.begin, u.end - u.begin);
      out[out.size() - (u.end - at)] = static_cast<char>(static_cast<unsigned char>(bytes[at]) ^ (1U << bit));
      ++counts.flipped;
    }
  }
  out.append(bytes, copied, std::string::npos);
  bytes = std::move(out);
  return counts;
}

}  // namespace gpsemu::faults
