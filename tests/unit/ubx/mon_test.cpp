// MON-HW, MON-HW2 and MON-RF byte for byte from the RF state (fields hand-checked against u-blox's
// interface descriptions, M8 protocol 18 and F9 HPG 1.32), and a changed state reaching them.
#include <gtest/gtest.h>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/mon.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace mon_test {

using test::hex;
using test::unhex;

TEST(UbxMon, HwOfTheSteadyStateIsByteExact) {
  const std::string expected = unhex(
      "00e00100 00000000 00000100 7fef0100"  // pinSel, pinBank, pinDir, pinVal
      "5900 440c"                            // noisePerMS 89, agcCnt 3140
      "02 01 05 00"                          // aStatus OK, aPower on, flags rtcCalib|jammingState 1 (ok), reserved
      "ffff0100"                             // usedMask
      "0a0b0c0d0e0f01000203ff10ff12133635"   // VP[17]
      "09 0000"                              // jamInd 9, reserved
      "00000000 00000000 00000000");         // pinIrq, pullH, pullL
  const std::string p = mon_hw(RfState{});
  EXPECT_EQ(p.size(), 60u);
  EXPECT_EQ(hex(p), hex(expected));
}

TEST(UbxMon, RfHasOneBlockPerBand) {
  const std::string block = "01 02 01 00000000 00000000 5900 440c 09 09 a6 fb a2 000000";
  // version 0, 2 blocks; each: blockId, jammingState 1, antStatus OK, antPower on, postStatus,
  // reserved, noisePerMS, agcCnt, jamInd, ofsI 9, magI 166, ofsQ -5, magQ 162, reserved.
  EXPECT_EQ(hex(mon_rf(RfState{}, ReceiverModel::ublox_f9p)),
            hex(unhex(std::string("00 02 0000 00") + block + "01" + block)));
  EXPECT_EQ(mon_rf(RfState{}, ReceiverModel::ublox_m9n).size(), 4u + 24);
}

TEST(UbxMon, Hw2IsByteExact) {
  // ofsI 9, magI 166, ofsQ -5, magQ 162, cfgSource ROM ('r'), reserved, lowLevCfg, reserved, postStatus, reserved
  EXPECT_EQ(hex(mon_hw2()), "09a6fba2" "72000000" "00000000" "0000000000000000" "00000000" "00000000");
}

TEST(UbxMon, AJammedShortedFrontEndShowsInBoth) {
  RfState rf;
  rf.jamming_indicator = 200;
  rf.jamming_state = 3;
  rf.antenna_status = 3;
  rf.agc_count = 600;
  const std::string hw = mon_hw(rf);
  EXPECT_EQ(get_u2(hw, 18), 600);
  EXPECT_EQ(get_u1(hw, 20), 3);                 // aStatus short
  EXPECT_EQ((get_u1(hw, 22) >> 2) & 0x03, 3);   // jammingState critical
  EXPECT_EQ(get_u1(hw, 45), 200);               // jamInd
  const std::string rf_p = mon_rf(rf, ReceiverModel::ublox_m9n);
  EXPECT_EQ(get_u1(rf_p, 4 + 1), 3);
  EXPECT_EQ(get_u1(rf_p, 4 + 2), 3);
  EXPECT_EQ(get_u1(rf_p, 4 + 16), 200);
}

}  // namespace mon_test
}  // namespace
}  // namespace gpsemu::ubx
