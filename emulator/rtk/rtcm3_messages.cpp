// RTCM3 message fields (see rtcm3_messages.hpp).
#include "emulator/rtk/rtcm3_messages.hpp"

#include <array>
#include <bit>
#include <cmath>

#include <fmt/format.h>

namespace gpsemu::rtk {
namespace {

constexpr double kPositionScaleM = 0.0001;  // DF025..DF028
constexpr int kMaxCells = 64;               // DF396: at most 64 cells

// Bits per satellite and per cell of the MSM body, MSM1..MSM7 (RTCM 10403.3 tables 3.5-78..84).
constexpr std::array<int, 8> kSatelliteBits{0, 10, 10, 10, 18, 36, 18, 36};
constexpr std::array<int, 8> kCellBits{0, 15, 27, 42, 48, 63, 65, 80};

std::optional<Gnss> msm_gnss(std::uint16_t type) {
  if (type < 1071 || type > 1137 || type % 10 == 0 || type % 10 > 7) return std::nullopt;
  static constexpr std::array<Gnss, 7> kByDecade{Gnss::gps, Gnss::glonass, Gnss::galileo, Gnss::sbas,
                                                 Gnss::qzss, Gnss::beidou, Gnss::navic};
  return kByDecade[static_cast<std::size_t>((type - 1070) / 10)];
}

BasePosition decode_base(BitReader& r, bool with_height) {
  BasePosition b;
  b.station_id = static_cast<std::uint16_t>(r.u(12));
  r.skip(6 + 4);  // ITRF year, GPS/GLONASS/Galileo/reference-station indicators
  b.ecef_x_m = static_cast<double>(r.s(38)) * kPositionScaleM;
  r.skip(2);  // single receiver oscillator, reserved
  b.ecef_y_m = static_cast<double>(r.s(38)) * kPositionScaleM;
  r.skip(2);  // quarter cycle indicator
  b.ecef_z_m = static_cast<double>(r.s(38)) * kPositionScaleM;
  if (with_height) b.antenna_height_m = static_cast<double>(r.u(16)) * kPositionScaleM;
  return b;
}

// The MSM header from after the station id; false when the payload is too short for the body the
// masks announce.
bool decode_msm(BitReader& r, MsmHeader& h, std::size_t payload_bytes) {
  h.epoch_time = static_cast<std::uint32_t>(r.u(30));
  h.more_follow = r.u(1) != 0;
  r.skip(3 + 7 + 2 + 2 + 1 + 3);  // IODS, reserved, clock steering, external clock, smoothing
  const std::uint64_t sat_mask = r.u(64);
  const std::uint64_t sig_mask = r.u(32);
  h.satellites = std::popcount(sat_mask);
  h.signals = std::popcount(sig_mask);
  const int mask_bits = h.satellites * h.signals;
  if (mask_bits > kMaxCells) return false;
  const std::uint64_t cell_mask = r.u(mask_bits);
  h.cells = std::popcount(cell_mask);
  const std::size_t body_bits = static_cast<std::size_t>(h.satellites * kSatelliteBits[static_cast<std::size_t>(h.msm)] +
                                                         h.cells * kCellBits[static_cast<std::size_t>(h.msm)]);
  return !r.overrun() && r.position_bits() + body_bits <= payload_bytes * 8;
}

}  // namespace

std::uint64_t BitReader::u(int bits) {
  std::uint64_t v = 0;
  for (int i = 0; i < bits; ++i, ++at_) {
    const std::size_t byte = at_ / 8;
    const unsigned bit = byte < bytes_.size() ? (static_cast<std::uint8_t>(bytes_[byte]) >> (7 - at_ % 8)) & 1u : 0u;
    v = (v << 1) | bit;
  }
  return v;
}

std::int64_t BitReader::s(int bits) {
  const std::uint64_t v = u(bits);
  if (bits <= 0 || bits >= 64) return static_cast<std::int64_t>(v);
  const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
  return static_cast<std::int64_t>(v ^ sign) - static_cast<std::int64_t>(sign);
}

void BitWriter::u(std::uint64_t value, int bits) {
  for (int i = bits - 1; i >= 0; --i) {
    if (used_bits_in_last_ == 8) {
      bytes_.push_back('\0');
      used_bits_in_last_ = 0;
    }
    const unsigned bit = i >= 64 ? 0u : static_cast<unsigned>((value >> i) & 1u);
    bytes_.back() = static_cast<char>(static_cast<std::uint8_t>(bytes_.back()) | (bit << (7 - used_bits_in_last_)));
    ++used_bits_in_last_;
  }
}

std::string_view gnss_name(Gnss gnss) {
  switch (gnss) {
    case Gnss::gps: return "GPS";
    case Gnss::glonass: return "GLONASS";
    case Gnss::galileo: return "Galileo";
    case Gnss::sbas: return "SBAS";
    case Gnss::qzss: return "QZSS";
    case Gnss::beidou: return "BeiDou";
    case Gnss::navic: return "NavIC";
  }
  return "?";
}

Rtcm3Message decode_rtcm3(std::string_view payload) {
  Rtcm3Message m;
  BitReader r(payload);
  m.type = static_cast<std::uint16_t>(r.u(12));
  if (m.type == 1005 || m.type == 1006) {
    m.base = decode_base(r, m.type == 1006);
    m.station_id = m.base->station_id;
    m.valid = !r.overrun();
  } else if (const std::optional<Gnss> gnss = msm_gnss(m.type)) {
    MsmHeader h;
    h.gnss = *gnss;
    h.msm = m.type % 10;
    m.station_id = static_cast<std::uint16_t>(r.u(12));
    m.valid = decode_msm(r, h, payload.size());
    m.msm = h;
  } else if (m.type == 1230) {
    m.station_id = static_cast<std::uint16_t>(r.u(12));
    r.skip(1 + 3);
    const int biases = std::popcount(static_cast<unsigned>(r.u(4)));
    r.skip(static_cast<std::size_t>(16 * biases));
    m.valid = !r.overrun();
  } else if (m.type == 4072) {
    m.subtype = static_cast<std::uint16_t>(r.u(12));
    m.valid = !r.overrun();
  } else {
    m.valid = !r.overrun();
  }
  return m;
}

std::string describe(const Rtcm3Message& m) {
  if (m.base) return fmt::format("{} base position", m.type);
  if (m.msm) return fmt::format("{} {} MSM{}", m.type, gnss_name(m.msm->gnss), m.msm->msm);
  if (m.type == 1230) return "1230 GLONASS biases";
  if (m.subtype) return fmt::format("4072.{} u-blox", *m.subtype);
  return fmt::format("{} other", m.type);
}

std::string encode_base_position(const BasePosition& base, bool with_height) {
  BitWriter w;
  w.u(with_height ? 1006 : 1005, 12);
  w.u(base.station_id, 12);
  w.u(0, 6);        // ITRF realization year
  w.u(0b1111, 4);   // GPS, GLONASS, Galileo, reference station (not physical)
  w.s(std::llround(base.ecef_x_m / kPositionScaleM), 38);
  w.u(0, 2);
  w.s(std::llround(base.ecef_y_m / kPositionScaleM), 38);
  w.u(0, 2);
  w.s(std::llround(base.ecef_z_m / kPositionScaleM), 38);
  if (with_height) w.u(static_cast<std::uint64_t>(std::llround(base.antenna_height_m / kPositionScaleM)), 16);
  return w.bytes();
}

std::string encode_msm(std::uint16_t type, std::uint16_t station_id, std::uint32_t epoch_time, int satellites,
                       int signals) {
  const int msm = type % 10;
  BitWriter w;
  w.u(type, 12);
  w.u(station_id, 12);
  w.u(epoch_time, 30);
  w.u(0, 1 + 3 + 7 + 2 + 2 + 1 + 3);
  // Satellites 1..n (DF394's first bits) and signals 2..n+1 (DF395; 2 is L1 C/A for GPS, 1 is reserved).
  w.u(satellites <= 0 ? 0 : satellites >= 64 ? ~std::uint64_t{0} : ~std::uint64_t{0} << (64 - satellites), 64);
  w.u(signals <= 0 ? 0 : signals >= 31 ? 0x7FFFFFFFu : ((std::uint64_t{1} << signals) - 1) << (31 - signals), 32);
  const int cells = satellites * signals;
  w.u(cells >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << cells) - 1, cells);
  if (msm >= 1 && msm <= 7) {
    // MSM4..7 start with each satellite's rough range in whole milliseconds (DF397): 70 + its
    // index, a plausible range (about 21 000 km); every other field zero (valid values).
    int body = satellites * kSatelliteBits[static_cast<std::size_t>(msm)] + cells * kCellBits[static_cast<std::size_t>(msm)];
    if (msm >= 4) {
      for (int i = 0; i < satellites; ++i) w.u(static_cast<std::uint64_t>(70 + i), 8);
      body -= 8 * satellites;
    }
    for (int left = body; left > 0; left -= 32) w.u(0, left < 32 ? left : 32);
  }
  return w.bytes();
}

std::string encode_1230(std::uint16_t station_id, unsigned signals_mask) {
  BitWriter w;
  w.u(1230, 12);
  w.u(station_id, 12);
  w.u(0, 1 + 3);                  // DF421 not aligned, reserved
  w.u(signals_mask & 0xFu, 4);    // DF422
  for (int bit = 3; bit >= 0; --bit) {
    if ((signals_mask >> bit) & 1u) w.s(0, 16);  // DF423..DF426: 0 m (units of 0.02 m)
  }
  return w.bytes();
}

}  // namespace gpsemu::rtk
