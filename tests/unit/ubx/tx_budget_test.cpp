// A u-blox's TX buffer on a line too slow for the epoch: whole messages that fit go out in order,
// the others are dropped whole and counted; what goes out still parses.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include <fmt/format.h>

#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/tx_budget.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::ubx {
namespace {
namespace tx_budget_test {

using namespace std::chrono_literals;

std::string sentence(std::string_view body) { return fmt::format("${}*{:02X}\r\n", body, nmea::checksum(body)); }

const std::string kGga = sentence("GPGGA,120000.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,");
const std::string kRmc = sentence("GPRMC,120000.00,A,4717.11399,N,00833.91590,E,0.004,77.52,241126,,,A");

TEST(UbxTxBudget, TheLineCarriesBaudOverTenBytesASecond) {
  EXPECT_EQ(line_bytes_per_period(9600, 100ms), 96u);
  EXPECT_EQ(line_bytes_per_period(9600, 1s), 960u);
  EXPECT_EQ(line_bytes_per_period(115200, 200ms), 2304u);
}

TEST(UbxTxBudget, AnEpochThatFitsIsUntouched) {
  std::string epoch = kGga + frame_bytes(MessageId{0x01, 0x07}, std::string(92, 'x'));
  const std::string before = epoch;
  const TxDrops drops = fit_epoch_to_line(epoch, before.size());
  EXPECT_EQ(drops.messages, 0u);
  EXPECT_EQ(epoch, before);
}

TEST(UbxTxBudget, MessagesThatDoNotFitAreDroppedWholeAndLaterOnesThatFitStillGo) {
  const std::string pvt = frame_bytes(MessageId{0x01, 0x07}, std::string(92, 'p'));    // 100 bytes
  const std::string status = frame_bytes(MessageId{0x01, 0x03}, std::string(16, 's'));  // 24 bytes
  std::string epoch = kGga + kRmc + pvt + status;
  const std::size_t budget = kGga.size() + kRmc.size() + 50;
  const TxDrops drops = fit_epoch_to_line(epoch, budget);
  EXPECT_EQ(drops.messages, 1u);
  EXPECT_EQ(drops.bytes, pvt.size());
  EXPECT_EQ(epoch, kGga + kRmc + status);

  FrameReader reader;
  (void)reader.feed(epoch);
  EXPECT_EQ(reader.stats().frames_ok, 1u);
  EXPECT_EQ(reader.stats().sentences_ok, 2u);
  EXPECT_EQ(reader.stats().bad_checksum + reader.stats().bad_sentences, 0u);
}

TEST(UbxTxBudget, ALineTooSlowForAnyMessageSendsNothing) {
  std::string epoch = kGga + kRmc;
  const TxDrops drops = fit_epoch_to_line(epoch, 10);
  EXPECT_EQ(drops.messages, 2u);
  EXPECT_EQ(drops.bytes, kGga.size() + kRmc.size());
  EXPECT_TRUE(epoch.empty());
}

}  // namespace tx_budget_test
}  // namespace
}  // namespace gpsemu::ubx
