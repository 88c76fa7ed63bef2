// PPS options through the binary: a GPIO chip that does not exist, modem PPS without a serial
// output, PPS with --fast and a bad spec each exit 2 with one clear message naming the problem.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace hw_pps_test {

TEST(PpsCliTest, MissingGpioChipExits2NamingIt) {
  const auto r = test::run({GPSEMU_BINARY, "--pps", "gpio:/dev/gpiochip9:3", "--output", "stdout", "--duration", "1"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("PPS gpio:/dev/gpiochip9:3: no GPIO chip '/dev/gpiochip9' on this machine"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.out, "");  // refused before any epoch went out
}

TEST(PpsCliTest, ModemPpsWithoutASerialOutputExits2) {
  const auto r = test::run({GPSEMU_BINARY, "--pps", "modem:DTR", "--output", "stdout", "--duration", "1"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--pps modem:DTR: drives a modem line of the serial output, but there is no serial output"),
            std::string::npos)
      << r.err;
}

TEST(PpsCliTest, PpsWithFastOrABadSpecOrWidthExits2) {
  const auto fast = test::run({GPSEMU_BINARY, "--pps", "modem:RTS", "--fast", "--output", "stdout", "--duration", "1"});
  EXPECT_EQ(fast.status, 2);
  EXPECT_NE(fast.err.find("cannot be used with --fast"), std::string::npos) << fast.err;
  const auto bad = test::run({GPSEMU_BINARY, "--pps", "modem:CTS", "--output", "stdout", "--duration", "1"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("invalid PPS spec 'modem:CTS'"), std::string::npos) << bad.err;
  const auto width = test::run({GPSEMU_BINARY, "--pps-width", "1.5", "--output", "stdout", "--duration", "1"});
  EXPECT_EQ(width.status, 2);
  EXPECT_NE(width.err.find("pps-width"), std::string::npos) << width.err;
  const auto polarity = test::run({GPSEMU_BINARY, "--pps-polarity", "up", "--output", "stdout", "--duration", "1"});
  EXPECT_EQ(polarity.status, 2);
  EXPECT_NE(polarity.err.find("pps-polarity"), std::string::npos) << polarity.err;
}

TEST(PpsCliTest, HelpListsThePpsOptionsWithUnitsAndDefaults) {
  const auto r = test::run({GPSEMU_BINARY, "--help"});
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("--pps SPEC"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--pps-width S"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("default 0.1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("serial:usb:VID:PID"), std::string::npos) << r.out;
}

}  // namespace hw_pps_test
}  // namespace
}  // namespace gpsemu
