// RF monitoring messages (see mon.hpp).
#include "emulator/ubx/mon.hpp"

#include <array>

#include "emulator/ubx/bytes.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::uint32_t kPinSel = 0x0001E000;   // pins used as peripheral functions (a NEO-M8N's)
constexpr std::uint32_t kPinBank = 0x00000000;
constexpr std::uint32_t kPinDir = 0x00010000;
constexpr std::uint32_t kPinVal = 0x0001EF7F;
constexpr std::uint32_t kUsedMask = 0x0001FFFF;
/// Virtual pin of each physical pin (VP[17]), as a NEO-M8N maps them.
constexpr std::array<std::uint8_t, 17> kVirtualPins = {0x0A, 0x0B, 0x0C, 0x0D, 0x0E, 0x0F, 0x01, 0x00, 0x02,
                                                        0x03, 0xFF, 0x10, 0xFF, 0x12, 0x13, 0x36, 0x35};
// I/Q imbalance of a healthy front end (MON-RF ofsI, magI, ofsQ, magQ).
constexpr int kOffsetI = 9, kOffsetQ = -5;
constexpr std::uint32_t kMagnitudeI = 166, kMagnitudeQ = 162;

}  // namespace

std::string mon_hw(const RfState& rf) {
  std::string p;
  p.reserve(60);
  put_u4(p, kPinSel);
  put_u4(p, kPinBank);
  put_u4(p, kPinDir);
  put_u4(p, kPinVal);
  put_u2(p, rf.noise_per_ms);
  put_u2(p, rf.agc_count);
  put_u1(p, rf.antenna_status);
  put_u1(p, rf.antenna_power);
  // flags: rtcCalib (the RTC is calibrated), jammingState in bits 2-3.
  put_u1(p, 0x01u | (static_cast<std::uint32_t>(rf.jamming_state & 0x03) << 2));
  put_u1(p, 0);  // reserved1
  put_u4(p, kUsedMask);
  for (const std::uint8_t vp : kVirtualPins) put_u1(p, vp);
  put_u1(p, rf.jamming_indicator);
  put_zeros(p, 2);  // reserved2
  put_u4(p, 0);     // pinIrq
  put_u4(p, 0);     // pullH
  put_u4(p, 0);     // pullL
  return p;
}

std::string mon_hw2() {
  std::string p;
  p.reserve(28);
  put_i1(p, kOffsetI);
  put_u1(p, kMagnitudeI);
  put_i1(p, kOffsetQ);
  put_u1(p, kMagnitudeQ);
  put_u1(p, 114);   // cfgSource: 'r', ROM
  put_zeros(p, 3);  // reserved0
  put_u4(p, 0);     // lowLevCfg
  put_zeros(p, 8);  // reserved1
  put_u4(p, 0);     // postStatus
  put_zeros(p, 4);  // reserved2
  return p;
}

std::string mon_rf(const RfState& rf, ReceiverModel model) {
  const int blocks = dual_band(model) ? 2 : 1;
  std::string p;
  p.reserve(4 + 24 * static_cast<std::size_t>(blocks));
  put_u1(p, 0);  // version
  put_u1(p, static_cast<std::uint32_t>(blocks));
  put_zeros(p, 2);
  for (int b = 0; b < blocks; ++b) {
    put_u1(p, static_cast<std::uint32_t>(b));  // blockId: 0 L1, 1 L2/L5
    put_u1(p, rf.jamming_state & 0x03u);       // flags: jammingState
    put_u1(p, rf.antenna_status);
    put_u1(p, rf.antenna_power);
    put_u4(p, 0);     // postStatus
    put_zeros(p, 4);  // reserved1
    put_u2(p, rf.noise_per_ms);
    put_u2(p, rf.agc_count);
    put_u1(p, rf.jamming_indicator);
    put_i1(p, kOffsetI);
    put_u1(p, kMagnitudeI);
    put_i1(p, kOffsetQ);
    put_u1(p, kMagnitudeQ);
    put_zeros(p, 3);  // reserved2
  }
  return p;
}

}  // namespace gpsemu::ubx
