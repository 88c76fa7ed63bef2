// RF monitoring messages (see mon.hpp).
#include "emulator/ubx/mon.hpp"

#include <array>

#include "emulator/ubx/layouts.hpp"

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
  PayloadWriter<layout::mon_hw> w;
  w.set<"pinSel">(kPinSel);
  w.set<"pinBank">(kPinBank);
  w.set<"pinDir">(kPinDir);
  w.set<"pinVal">(kPinVal);
  w.set<"noisePerMS">(rf.noise_per_ms);
  w.set<"agcCnt">(rf.agc_count);
  w.set<"aStatus">(rf.antenna_status);
  w.set<"aPower">(rf.antenna_power);
  // flags: rtcCalib (the RTC is calibrated), jammingState in bits 2-3.
  w.set<"flags">(0x01u | (static_cast<std::uint32_t>(rf.jamming_state & 0x03) << 2));
  w.set<"usedMask">(kUsedMask);
  for (std::size_t i = 0; i < kVirtualPins.size(); ++i) w.set<"VP">(kVirtualPins[i], i);
  w.set<"jamInd">(rf.jamming_indicator);
  return std::move(w).bytes();  // pinIrq, pullH, pullL 0
}

std::string mon_hw2() {
  PayloadWriter<layout::mon_hw2> w;
  w.set<"ofsI">(kOffsetI);
  w.set<"magI">(kMagnitudeI);
  w.set<"ofsQ">(kOffsetQ);
  w.set<"magQ">(kMagnitudeQ);
  w.set<"cfgSource">(114);      // 'r', ROM
  return std::move(w).bytes();  // lowLevCfg, postStatus 0
}

std::string mon_rf(const RfState& rf, ReceiverModel model) {
  const int blocks = dual_band(model) ? 2 : 1;
  PayloadWriter<layout::mon_rf> header;
  header.set<"version">(0);
  header.set<"nBlocks">(blocks);
  std::string p = std::move(header).bytes();
  for (int b = 0; b < blocks; ++b) {
    PayloadWriter<layout::mon_rf_block> w;
    w.set<"blockId">(b);                       // 0 L1, 1 L2/L5
    w.set<"flags">(rf.jamming_state & 0x03u);  // jammingState
    w.set<"antStatus">(rf.antenna_status);
    w.set<"antPower">(rf.antenna_power);
    w.set<"postStatus">(0);
    w.set<"noisePerMS">(rf.noise_per_ms);
    w.set<"agcCnt">(rf.agc_count);
    w.set<"jamInd">(rf.jamming_indicator);
    w.set<"ofsI">(kOffsetI);
    w.set<"magI">(kMagnitudeI);
    w.set<"ofsQ">(kOffsetQ);
    w.set<"magQ">(kMagnitudeQ);
    p += w.bytes();
  }
  return p;
}

}  // namespace gpsemu::ubx
