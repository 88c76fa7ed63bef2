// make_fault: a [[fault]] table's keys into a Fault, or one clear message naming the key.
#include "emulator/faults/fault.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace gpsemu::faults {
namespace {
namespace fault_test {

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

TEST(MakeFault, EachKindFillsItsOwnAlternative) {
  // The fewest keys each kind takes, in catalogue order.
  const std::vector<FaultKeys> minimal{
      {},
      {},
      {{"east_m", 1.0}},
      {{"north_m", 2.0}},
      {{"quality", std::string("dgps")}},
      {{"satellites", 5.0}},
      {},
      {{"db", 10.0}},
      {{"mask", std::string("tree-line")}},
      {{"speed_mps", 3.0}},
      {{"mode", std::string("rollover")}},
      {},
      {{"rate", 0.5}},
      {{"delay_ms", 120.0}},
  };
  ASSERT_EQ(minimal.size(), catalogue().size());
  for (std::size_t i = 0; i < catalogue().size(); ++i) {
    const KindInfo& k = catalogue()[i];
    FaultKeys keys{{"kind", std::string(k.name)}};
    keys.insert(keys.end(), minimal[i].begin(), minimal[i].end());
    const Fault f = make_fault(keys);
    EXPECT_EQ(f.kind(), k.kind) << k.name;
    EXPECT_EQ(f.params.index(), i) << k.name;
    EXPECT_EQ(kind_of(default_params(k.kind)), k.kind) << k.name;
    EXPECT_EQ(f.parameters().substr(0, k.name.size()), k.name);
  }
  const Fault latency = make_fault({{"kind", std::string("latency")}, {"delay_ms", 120.0}});
  ASSERT_TRUE(latency.is<Latency>());
  EXPECT_EQ(latency.as<Latency>()->delay_ms, 120.0);
  EXPECT_EQ(latency.as<Jam>(), nullptr);
  const Fault wrong = make_fault({{"kind", std::string("wrong")}, {"north_m", 2.0}, {"ramp_s", 4.0}});
  EXPECT_EQ(std::get<Wrong>(wrong.params).offset_m.north_m, 2.0);
  EXPECT_EQ(wrong.ramp_s, 4.0);  // the ramp is the common part's
  // Another kind's key stays refused, naming the kind's own.
  EXPECT_NE(error_of({{"kind", std::string("latency")}, {"delay_ms", 1.0}, {"db", 3.0}})
                .find("db: not a parameter of latency (its parameters: delay_ms, jitter_ms;"),
            std::string::npos);
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
  EXPECT_NE(error_of({{"kind", std::string("jam")}, {"db", 20.0}, {"leave", 3.0}}).find("db or leave, not both"),
            std::string::npos);
  EXPECT_NE(error_of({{"kind", std::string("jam")}, {"leave", 2.5}}).find("whole number"), std::string::npos);
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

}  // namespace fault_test
}  // namespace
}  // namespace gpsemu::faults
