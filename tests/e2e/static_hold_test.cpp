// The emulator's static hold and altitude decimals through the binary (issue 27): with
// --hold-radius a stationary receiver repeats its last position in most epochs, as SiRF and SkyTraq
// static navigation do; without it, never; a moving one (sim:circle) is never held; --alt-decimals
// writes the GGA altitude with that many decimals.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "emulator/calibration/hold_fit.hpp"
#include "emulator/calibration/receiver_log.hpp"
#include "tests/support/process.hpp"

namespace gpsemu::calibration {
namespace {
namespace static_hold_test {

// The share of repeated positions of the run's GGA, and its altitude decimals.
std::pair<double, int> run(std::vector<std::string> args) {
  args.insert(args.end(), {"--sentences", "GGA", "--rate", "1", "--duration", "120", "--resolution", "6", "--noise",
                           "gauss-markov", "--gm-order", "2", "--gm-sigma", "0.4,0.3,0.6", "--gm-tau", "15,20,15"});
  const auto r = test::run_fast(GPSEMU_BINARY, args);
  EXPECT_EQ(r.status, 0) << r.err;
  ReceiverLog log = read_receiver_log(r.out);
  EXPECT_GE(log.fixes.size(), 110u);
  const int decimals = log.alt_decimals;
  return {repeat_share(to_enu_series(log).axis_m), decimals};
}

TEST(StaticHoldE2e, StationaryReceiverRepeatsItsPositionOnlyWithHold) {
  const auto [held, held_decimals] = run({"--hold-radius", "0.15", "--alt-decimals", "2"});
  EXPECT_GT(held, 0.5);
  EXPECT_EQ(held_decimals, 2);
  const auto [free, free_decimals] = run({});
  EXPECT_LT(free, 0.05);
  EXPECT_EQ(free_decimals, 1);  // the default: 0.1 m steps
}

TEST(StaticHoldE2e, MovingReceiverIsNotHeld) {
  // sim:circle at its default 2 m/s, far above the 0.3 m/s hold speed (sim:line stops after a while).
  const auto [share, decimals] = run({"--source", "sim:circle", "--hold-radius", "5", "--alt-decimals", "0"});
  EXPECT_LT(share, 0.05);
  EXPECT_EQ(decimals, 0);
}

}  // namespace static_hold_test
}  // namespace
}  // namespace gpsemu::calibration
