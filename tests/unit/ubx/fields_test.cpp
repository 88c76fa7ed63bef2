// Payloads filled by field name (fields.hpp): each field lands at its offset,
// little-endian and cut to its size; arrays, text and floats; the layouts'
// offsets are the interface description's.
#include <gtest/gtest.h>

#include "emulator/ubx/layouts.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu::ubx {
namespace {
namespace fields_test {

using test::hex;
using test::unhex;

TEST(UbxFields, IntegersLandAtTheirOffsetsLittleEndianAndCutToTheirSize) {
  PayloadWriter<layout::nav_posllh> w;
  w.set<"iTOW">(0x01020304u).set<"lon">(-2).set<"vAcc">(0x1122334455ull);  // vAcc U4: the high byte is cut
  EXPECT_EQ(hex(w.bytes()), hex(unhex("04030201 feffffff 00000000 00000000 00000000 00000000 55443322")));
}

TEST(UbxFields, ArrayElementsTextAndFloats) {
  PayloadWriter<layout::mon_hw> hw;
  hw.set<"VP">(0xAB, 16);
  EXPECT_EQ(
      static_cast<unsigned char>(hw.bytes()[field_offset(layout::mon_hw, field_index(layout::mon_hw, "VP")) + 16]),
      0xABu);
  PayloadWriter<layout::mon_ver> ver;
  ver.set_text<"hwVersion">("00190000-and-more");  // cut at 10 characters
  EXPECT_EQ(ver.bytes().substr(30, 10), "00190000-a");
  EXPECT_EQ(ver.bytes().substr(0, 30), std::string(30, '\0'));
  PayloadWriter<layout::nav_cov> cov;
  cov.set<"posCovNN">(1.0f);  // IEEE 754 single 1.0 = 0x3f800000 at offset 16
  EXPECT_EQ(hex(cov.bytes().substr(16, 4)), "0000803f");
}

TEST(UbxFields, OffsetsAreTheInterfaceDescriptions) {
  // Spot checks of fields drivers read by offset (PX4's ubx.h, ArduPilot's
  // AP_GPS_UBLOX.h).
  EXPECT_EQ(field_offset(layout::nav_pvt, field_index(layout::nav_pvt, "hAcc")), 40u);
  EXPECT_EQ(field_offset(layout::nav_pvt, field_index(layout::nav_pvt, "headMot")), 64u);
  EXPECT_EQ(field_offset(layout::nav_pvt, field_index(layout::nav_pvt, "pDOP")), 76u);
  EXPECT_EQ(field_offset(layout::nav_relposned, field_index(layout::nav_relposned, "accN")), 36u);
  EXPECT_EQ(field_offset(layout::nav_relposned, field_index(layout::nav_relposned, "flags")), 60u);
  EXPECT_EQ(field_offset(layout::mon_hw, field_index(layout::mon_hw, "jamInd")), 45u);
  EXPECT_EQ(field_index(layout::nav_pvt, "noSuchField"), layout::nav_pvt.size());
}

}  // namespace fields_test
}  // namespace
}  // namespace gpsemu::ubx
