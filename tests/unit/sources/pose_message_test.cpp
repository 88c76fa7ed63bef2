// The pose message decoder: every accepted form, and one refusal reason per kind of bad input.
#include <gtest/gtest.h>

#include <string>

#include "emulator/sources/pose_message.hpp"

namespace gpsemu::sources {
namespace {
namespace pose_message_test {

PoseMessage accepted(std::string_view text) {
  const auto r = decode_pose(text);
  if (const auto* why = std::get_if<PoseReject>(&r)) {
    ADD_FAILURE() << "'" << text << "' refused: " << to_string(*why);
    return {};
  }
  return std::get<PoseMessage>(r);
}

std::string refused(std::string_view text) {
  const auto r = decode_pose(text);
  if (const auto* why = std::get_if<PoseReject>(&r)) return to_string(*why);
  return "accepted";
}

TEST(PoseMessage, LocalPositionWithTimeAndVelocity) {
  const auto m = accepted(R"({"t": 12.5, "x": 1.5, "y": -2, "z": 0.25, "ve": 1, "vn": -0.5, "vu": 0.1})");
  ASSERT_TRUE(m.sender_time_s);
  EXPECT_DOUBLE_EQ(*m.sender_time_s, 12.5);
  const auto& p = std::get<Enu>(m.position);
  EXPECT_DOUBLE_EQ(p.east_m, 1.5);
  EXPECT_DOUBLE_EQ(p.north_m, -2.0);
  EXPECT_DOUBLE_EQ(p.up_m, 0.25);
  ASSERT_TRUE(m.velocity_mps);
  EXPECT_DOUBLE_EQ(m.velocity_mps->east_m, 1.0);
  EXPECT_DOUBLE_EQ(m.velocity_mps->north_m, -0.5);
  EXPECT_DOUBLE_EQ(m.velocity_mps->up_m, 0.1);
}

TEST(PoseMessage, ZVuAndTimeAreOptional) {
  const auto m = accepted(R"({"x": 3, "y": 4, "ve": 2, "vn": 0})");
  EXPECT_FALSE(m.sender_time_s);
  EXPECT_DOUBLE_EQ(std::get<Enu>(m.position).up_m, 0.0);
  ASSERT_TRUE(m.velocity_mps);
  EXPECT_DOUBLE_EQ(m.velocity_mps->up_m, 0.0);
  EXPECT_FALSE(accepted(R"({"x": 3, "y": 4})").velocity_mps);
}

TEST(PoseMessage, GeodeticWithAndWithoutAltitude) {
  const auto m = accepted(R"({"lat": 43.0725, "lon": -89.4125, "alt": 261.5})");
  const auto& g = std::get<GeodeticPose>(m.position);
  EXPECT_DOUBLE_EQ(g.lat_deg, 43.0725);
  EXPECT_DOUBLE_EQ(g.lon_deg, -89.4125);
  ASSERT_TRUE(g.alt_msl_m);
  EXPECT_DOUBLE_EQ(*g.alt_msl_m, 261.5);
  EXPECT_FALSE(std::get<GeodeticPose>(accepted(R"({"lat": -90, "lon": 180})").position).alt_msl_m);
}

TEST(PoseMessage, WhitespaceKeyOrderTrailingCarriageReturnAndIntegersAreFine) {
  accepted("  {\"y\":1,\n\"x\":2}  \r");
  accepted(R"({"lon": 0, "lat": 0, "t": 0})");
  accepted(R"({"x": 1e3, "y": -2E-3})");
}

TEST(PoseMessage, MalformedJsonIsNotJson) {
  EXPECT_EQ(refused(""), "not_json");
  EXPECT_EQ(refused("garbage"), "not_json");
  EXPECT_EQ(refused(R"({"x": 1, "y": 2)"), "not_json");             // truncated
  EXPECT_EQ(refused(R"({"x": 1, "y": 2}})"), "not_json");           // trailing bytes
  EXPECT_EQ(refused(R"({"x": 1, "y": 2}{"x": 1, "y": 2})"), "not_json");  // two messages in one
  EXPECT_EQ(refused(std::string("{\"x\": 1, \0\"y\": 2}", 17)), "not_json");
  EXPECT_EQ(refused("\xff\xfe{}"), "not_json");
}

TEST(PoseMessage, NotAnObject) {
  EXPECT_EQ(refused("[1, 2, 3]"), "not_object");
  EXPECT_EQ(refused("42"), "not_object");
  EXPECT_EQ(refused(R"("x")"), "not_object");
  EXPECT_EQ(refused("null"), "not_object");
}

TEST(PoseMessage, MissingKeys) {
  EXPECT_EQ(refused("{}"), "missing_key");
  EXPECT_EQ(refused(R"({"t": 1})"), "missing_key");
  EXPECT_EQ(refused(R"({"lat": 43})"), "missing_key");
  EXPECT_EQ(refused(R"({"lon": 43, "alt": 3})"), "missing_key");
  EXPECT_EQ(refused(R"({"x": 1})"), "missing_key");
  EXPECT_EQ(refused(R"({"y": 1, "z": 1})"), "missing_key");
  EXPECT_EQ(refused(R"({"x": 1, "y": 2, "ve": 1})"), "missing_key");
  EXPECT_EQ(refused(R"({"x": 1, "y": 2, "vu": 1})"), "missing_key");
  EXPECT_EQ(refused(R"({"ve": 1, "vn": 1})"), "missing_key");
}

TEST(PoseMessage, ExtraOrRepeatedKeys) {
  EXPECT_EQ(refused(R"({"x": 1, "y": 2, "heading": 90})"), "extra_key");
  EXPECT_EQ(refused(R"({"lattitude": 43, "lon": 1})"), "extra_key");
  EXPECT_EQ(refused(R"({"X": 1, "y": 2})"), "extra_key");  // keys are case-sensitive
  EXPECT_EQ(refused(R"({"x": 1, "y": 2, "x": 3})"), "extra_key");
}

TEST(PoseMessage, BothPositionFormsAreMixed) {
  EXPECT_EQ(refused(R"({"lat": 1, "lon": 2, "x": 3, "y": 4})"), "mixed_position");
  EXPECT_EQ(refused(R"({"x": 3, "y": 4, "alt": 5})"), "mixed_position");
}

TEST(PoseMessage, ValuesThatAreNotNumbers) {
  EXPECT_EQ(refused(R"({"x": "1", "y": 2})"), "not_a_number");
  EXPECT_EQ(refused(R"({"x": true, "y": 2})"), "not_a_number");
  EXPECT_EQ(refused(R"({"x": null, "y": 2})"), "not_a_number");
  EXPECT_EQ(refused(R"({"x": [1], "y": 2})"), "not_a_number");
  EXPECT_EQ(refused(R"({"x": {"v": 1}, "y": 2})"), "not_a_number");
}

TEST(PoseMessage, NanAndInfinityAreNotFinite) {
  EXPECT_EQ(refused(R"({"x": NaN, "y": 2})"), "not_finite");       // Python json.dumps
  EXPECT_EQ(refused(R"({"x": 1, "y": Infinity})"), "not_finite");
  EXPECT_EQ(refused(R"({"x": -Infinity, "y": 2})"), "not_finite");
  EXPECT_EQ(refused(R"({"x": nan, "y": 2})"), "not_finite");       // C printf
  EXPECT_EQ(refused(R"({"x": 1, "y": -inf})"), "not_finite");
  EXPECT_EQ(refused(R"({"x": 1e999, "y": 2})"), "not_finite");     // beyond double range
}

TEST(PoseMessage, OutOfRange) {
  EXPECT_EQ(refused(R"({"lat": 90.0001, "lon": 0})"), "out_of_range");
  EXPECT_EQ(refused(R"({"lat": -91, "lon": 0})"), "out_of_range");
  EXPECT_EQ(refused(R"({"lat": 0, "lon": 180.5})"), "out_of_range");
  EXPECT_EQ(refused(R"({"lat": 0, "lon": 0, "alt": -20000})"), "out_of_range");
  EXPECT_EQ(refused(R"({"x": 2e7, "y": 0})"), "out_of_range");
  EXPECT_EQ(refused(R"({"x": 0, "y": 0, "ve": 0, "vn": 2e4})"), "out_of_range");
}

TEST(PoseMessage, OverlongMessagesAreTooLargeBeforeParsing) {
  std::string big = R"({"x": 1, "y": 2})";
  big.append(kMaxPoseMessageBytes, ' ');
  EXPECT_EQ(refused(big), "too_large");
  EXPECT_EQ(refused(std::string(70 * 1024, '{')), "too_large");  // over 64 KiB
  std::string fits = R"({"x": 1, "y": 2})";
  fits.append(kMaxPoseMessageBytes - fits.size(), ' ');
  accepted(fits);
}

TEST(PoseMessage, DeepNestingIsRefusedWithoutRecursion) {
  EXPECT_EQ(refused(std::string(4000, '[')), "not_object");
  EXPECT_EQ(refused("{\"x\":" + std::string(4000, '[')), "not_a_number");
}

TEST(PoseMessage, EveryReasonHasAName) {
  for (std::size_t i = 0; i < kPoseRejectCount; ++i) {
    EXPECT_STRNE(to_string(static_cast<PoseReject>(i)), "unknown") << i;
  }
}

TEST(PoseMessage, SenderTimeBeyondTheLimitIsOutOfRange) {
  EXPECT_EQ(refused(R"({"t": 1e300, "x": 0, "y": 0})"), "out_of_range");
  EXPECT_EQ(refused(R"({"t": -1e300, "x": 0, "y": 0})"), "out_of_range");
  EXPECT_EQ(refused(R"({"t": 4.1e9, "x": 0, "y": 0})"), "out_of_range");
  EXPECT_TRUE(accepted(R"({"t": 1.7e9, "x": 0, "y": 0})").sender_time_s);   // Unix time
  EXPECT_TRUE(accepted(R"({"t": -12.5, "x": 0, "y": 0})").sender_time_s);   // any epoch
}

}  // namespace pose_message_test
}  // namespace
}  // namespace gpsemu::sources
