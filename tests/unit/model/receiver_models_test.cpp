// The receiver table (emulator/model/receiver_models.hpp): one row a model, in the enum's order,
// names unique and found again, and the facts the protocols and the sky read from it.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "emulator/model/receiver_models.hpp"

namespace gpsemu {
namespace {

TEST(ReceiverTable, EveryModelHasOneRowFoundAgainByItsName) {
  ASSERT_EQ(receiver_table().size(), kReceiverModels);
  std::set<std::string> names;
  for (std::size_t i = 0; i < receiver_table().size(); ++i) {
    const ReceiverFacts& f = receiver_table()[i];
    EXPECT_TRUE(names.insert(std::string(f.name)).second) << f.name;
    EXPECT_EQ(receiver_model_from_name(f.name), static_cast<ReceiverModel>(i)) << f.name;
    EXPECT_EQ(&facts_of(static_cast<ReceiverModel>(i)), &f);
    EXPECT_FALSE(f.vendor.empty());
    EXPECT_FALSE(f.module.empty());
    EXPECT_GT(f.tracking.channels, 0) << f.name;
    EXPECT_GT(f.tracking.uere_m, 0.0) << f.name;
    EXPECT_GT(f.fastest_solution_period.count(), 0) << f.name;
    EXPECT_GT(f.default_baud, 0u) << f.name;
    // What it writes after a reset it can be set to write.
    f.nmea_default.for_each([&](nmea::SentenceType t) { EXPECT_TRUE(f.nmea_written.contains(t)) << f.name; });
  }
  EXPECT_EQ(receiver_model_from_name("ublox-f10"), std::nullopt);
}

TEST(ReceiverTable, TheRowsSayWhatEachModuleIs) {
  const ReceiverFacts& f9p = facts_of(ReceiverModel::ublox_f9p);
  EXPECT_EQ(f9p.name, "ublox-f9p");
  EXPECT_TRUE(f9p.tracking.dual_band);
  EXPECT_EQ(f9p.tracking.channels, 184);
  EXPECT_EQ(f9p.corrections, Corrections::rtk);
  EXPECT_TRUE(f9p.moving_base);
  EXPECT_EQ(f9p.fastest_solution_period, std::chrono::milliseconds{50});
  EXPECT_EQ(facts_of(ReceiverModel::ublox_m9n).corrections, Corrections::dgnss);
  EXPECT_EQ(facts_of(ReceiverModel::ublox_m10).corrections, Corrections::none);
  EXPECT_EQ(facts_of(ReceiverModel::ublox_m10).default_baud, 9600u);
  EXPECT_FALSE(facts_of(ReceiverModel::ublox_m8n).tracking.systems.contains(nmea::GnssSystem::galileo));
  EXPECT_TRUE(facts_of(ReceiverModel::ublox_m9n).tracking.systems.contains(nmea::GnssSystem::beidou));
  for (const ReceiverFacts& f : receiver_table()) {
    EXPECT_FALSE(f.nmea_written.contains(nmea::SentenceType::hdt)) << f.name;  // u-blox: heading in RELPOSNED
    EXPECT_TRUE(f.nmea_written.contains(nmea::SentenceType::gst)) << f.name;
  }
}

}  // namespace
}  // namespace gpsemu
