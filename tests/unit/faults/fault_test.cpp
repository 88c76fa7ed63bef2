// make_fault: a [[fault]] table's keys into a Fault, or one clear message naming the key.
#include "emulator/faults/fault.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace gpsemu::faults {
namespace {

std::string error_of(const FaultKeys& keys) {
  try {
    (void)make_fault(keys);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(MakeFault, TheIssuesFormWithParametersByName) {
  const Fault jump = make_fault({{"kind", std::string("jump")}, {"at", 30.0}, {"duration", 10.0}, {"east_m", 20.0}});
  EXPECT_EQ(jump.kind(), FaultKind::jump);
  EXPECT_DOUBLE_EQ(jump.at_s, 30.0);
  ASSERT_TRUE(jump.duration_s);
  EXPECT_DOUBLE_EQ(*jump.duration_s, 10.0);
  EXPECT_DOUBLE_EQ(std::get<Jump>(jump.params).offset_m.east_m, 20.0);
  EXPECT_FALSE(jump.receiver);  // every receiver

  const Fault jam = make_fault({{"kind", std::string("jam")}, {"at", 5.0}, {"end", 15.0}, {"db", 25.0},
                                {"ramp_s", 5.0}, {"receiver", 2.0}});
  ASSERT_TRUE(jam.duration_s);
  EXPECT_DOUBLE_EQ(*jam.duration_s, 10.0);
  EXPECT_EQ(jam.receiver, 2);
  EXPECT_DOUBLE_EQ(jam.strength_at(7.5), 0.5);
  EXPECT_DOUBLE_EQ(jam.strength_at(12.0), 1.0);
  EXPECT_TRUE(jam.active_at(5.0));
  EXPECT_TRUE(jam.active_at(14.999));
  EXPECT_FALSE(jam.active_at(15.0));

  const Fault outage = make_fault({{"kind", std::string("outage")}, {"at", 1.0}});
  EXPECT_FALSE(outage.duration_s);  // to the end
  EXPECT_TRUE(outage.active_at(1e6));
  const Fault rtk_float = make_fault({{"kind", std::string("fix-quality")}, {"quality", std::string("rtk-float")}});
  EXPECT_EQ(std::get<ForcedQuality>(rtk_float.params).quality, nmea::FixQuality::rtk_float);
}

TEST(MakeFault, BadKeysAndValuesNameTheKey) {
  EXPECT_NE(error_of({{"at", 1.0}}).find("kind: missing"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("meteor")}}).find("unknown fault 'meteor'"), std::string::npos);
  // A parameter of another kind, and the parameters this kind takes.
  const std::string wrong_key = error_of({{"kind", std::string("outage")}, {"db", 3.0}});
  EXPECT_NE(wrong_key.find("db: not a parameter of outage"), std::string::npos) << wrong_key;
  EXPECT_NE(error_of({{"kind", std::string("jump")}, {"east", 3.0}}).find("east_m, north_m"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("jam")}, {"db", 99.0}}).find("db: 99 is outside [0, 60]"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("jam")}}).find("db: missing"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("outage")}, {"at", -1.0}}).find("at:"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("outage")}, {"duration", 0.0}}).find("duration: must be > 0"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("outage")}, {"at", 5.0}, {"end", 3.0}}).find("not after at"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("outage")}, {"duration", 1.0}, {"end", 3.0}}).find("not both"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("outage")}, {"receiver", std::string("first")}}).find("receiver:"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("outage")}, {"receiver", 1.5}}).find("whole number"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("fix-quality")}, {"quality", std::string("none")}}).find("outage"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("degrade")}}).find("at least one"), std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("jam")}, {"db", std::string("25")}}).find("expected a number"), std::string::npos);
  EXPECT_NE(error_of({{"kind", 3.0}}).find("expected a string"), std::string::npos);
}

}  // namespace
}  // namespace gpsemu::faults
