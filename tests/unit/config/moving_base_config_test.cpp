// A moving-base pair in a fleet's [[receiver]] tables: role and antenna-offset are read per
// receiver, the rover learns its base's antenna, and the refusals name what is wrong (no base,
// two bases, a rover without UBX, one antenna for both, bad text).
#include <gtest/gtest.h>

#include <string>

#include "emulator/config/fleet_config.hpp"
#include "tests/support/config_files.hpp"

namespace gpsemu {
namespace {
namespace moving_base_config_test {

std::string write_temp(const std::string& name, const std::string& text) {
  return test::write_temp("gpsemu_moving_base_", name, text);
}

std::string pair_file(const std::string& base_keys, const std::string& rover_keys) {
  return "source = \"sim:circle\"\n"
         "[[receiver]]\n"
         "output = \"file:/tmp/gpsemu-mb-base.bin\"\n" +
         base_keys +
         "[[receiver]]\n"
         "output = \"file:/tmp/gpsemu-mb-rover.bin\"\n" +
         rover_keys;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(MovingBaseConfig, RoverLearnsItsBasesAntenna) {
  const auto file = write_temp("ok.toml", pair_file("role = \"moving-base\"\nantenna-offset = \"-0.5,0,-0.1\"\n",
                                                    "role = \"rover\"\nantenna-offset = \"0.5,0,-0.1\"\nprotocol = \"ubx\"\n"
                                                    "receiver = \"ublox-f9p\"\n"));
  const auto fleet = build_config(file, {}).receivers;
  ASSERT_EQ(fleet.size(), 2u);
  EXPECT_EQ(fleet[0].moving_base.role, heading::Role::moving_base);
  EXPECT_EQ(fleet[1].moving_base.role, heading::Role::rover);
  EXPECT_DOUBLE_EQ(fleet[1].moving_base.antenna.forward_m, 0.5);
  EXPECT_DOUBLE_EQ(fleet[1].moving_base.base_antenna.forward_m, -0.5);
  EXPECT_DOUBLE_EQ(fleet[1].moving_base.base_antenna.down_m, -0.1);
}

TEST(MovingBaseConfig, RefusalsNameTheProblem) {
  struct Case {
    std::string base, rover, expected;
  };
  const Case cases[] = {
      {"", "role = \"rover\"\nprotocol = \"ubx\"\nantenna-offset = \"1,0,0\"\n", "needs a receiver with role = \"moving-base\""},
      {"role = \"moving-base\"\n", "role = \"moving-base\"\n", "both moving-base"},
      {"role = \"moving-base\"\n", "role = \"rover\"\nantenna-offset = \"1,0,0\"\n", "needs protocol = \"ubx\""},
      {"role = \"moving-base\"\n", "role = \"rover\"\nprotocol = \"ubx\"\n", "same antenna offset"},
      {"role = \"base\"\n", "", "unknown role 'base'"},
      {"antenna-offset = \"1,2\"\n", "", "antenna-offset"},
  };
  int n = 0;
  for (const Case& c : cases) {
    const auto file = write_temp("bad" + std::to_string(n++) + ".toml", pair_file(c.base, c.rover));
    const std::string error = test::config_error_of(file, {});
    EXPECT_TRUE(contains(error, c.expected)) << error;
  }
}

}  // namespace moving_base_config_test
}  // namespace
}  // namespace gpsemu
