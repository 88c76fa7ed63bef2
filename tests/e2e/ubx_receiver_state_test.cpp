// The receiver state through the binary (--protocol ubx, --fast, NAV-PVT every second): a cold
// start has no valid time at its first epoch (no satellite yet), date and time valid while it
// acquires, fully resolved with the first fix and confirmed 2 s later; an outage invalidates the
// time until the satellites come back; with --noise none every fix reports nonzero hAcc, vAcc,
// sAcc and headAcc (the floors of an autonomous fix).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace ubx_receiver_state_test {

struct Pvt {
  int valid = 0, flags2 = 0, fix_type = 0;
  std::uint32_t h_acc_mm = 0, v_acc_mm = 0, s_acc_mm_s = 0, head_acc = 0;
};

std::vector<Pvt> pvts_in(const std::string& bytes) {
  std::vector<Pvt> out;
  ubx::FrameReader reader;
  for (const ubx::ClientMessage& m : reader.feed(bytes)) {
    const auto* f = std::get_if<ubx::Frame>(&m);
    if (f == nullptr || f->id != ubx::msg::nav_pvt) continue;
    const std::string& p = f->payload;
    out.push_back({ubx::get_u1(p, 11), ubx::get_u1(p, 22), ubx::get_u1(p, 20), ubx::get_u4(p, 40), ubx::get_u4(p, 44),
                   ubx::get_u4(p, 68), ubx::get_u4(p, 72)});
  }
  return out;
}

TEST(UbxReceiverState, ColdStartAndOutageTimeFlagsAndAccuraciesInNavPvt) {
  const test::Result r = test::run_fast(GPSEMU_BINARY, {"--protocol", "ubx", "--noise", "none", "--cold-start", "20",
                                                        "--outage", "60+10", "--duration", "90", "--seed", "3",
                                                        "--source", "sim:circle"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<Pvt> pvt = pvts_in(r.out);
  ASSERT_EQ(pvt.size(), 90u);
  EXPECT_EQ(pvt[0].valid, 0x00);  // no satellite yet: no date, no time
  EXPECT_EQ(pvt[0].flags2, 0x20);
  for (int k = 1; k < 20; ++k) {
    EXPECT_EQ(pvt[k].valid, 0x03) << k;  // acquiring: date and time, not resolved
    EXPECT_EQ(pvt[k].fix_type, 0) << k;
  }
  EXPECT_NE(pvt[20].fix_type, 0);
  EXPECT_EQ(pvt[20].valid, 0x07);   // the first fix resolves UTC
  EXPECT_EQ(pvt[21].flags2, 0x20);  // not yet confirmed
  EXPECT_EQ(pvt[22].flags2, 0xE0);  // confirmed 2 s after the first fix
  for (int k = 60; k < 70; ++k) {
    EXPECT_EQ(pvt[k].valid, 0x00) << k;  // the outage: no satellites, no time
    EXPECT_EQ(pvt[k].flags2, 0x20) << k;
  }
  EXPECT_EQ(pvt[70].valid, 0x07);
  EXPECT_EQ(pvt[70].flags2, 0x20);
  EXPECT_EQ(pvt[72].flags2, 0xE0);
  for (std::size_t k = 0; k < pvt.size(); ++k) {
    if (pvt[k].fix_type == 0) continue;
    EXPECT_GE(pvt[k].h_acc_mm, 500u) << k;
    EXPECT_GE(pvt[k].v_acc_mm, 750u) << k;
    EXPECT_GE(pvt[k].s_acc_mm_s, 50u) << k;
    EXPECT_GT(pvt[k].head_acc, 0u) << k;
  }
}

}  // namespace ubx_receiver_state_test
}  // namespace
}  // namespace gpsemu
