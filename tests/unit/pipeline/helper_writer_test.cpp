// HelperWriter: the posted part is written on another thread, not before its time, once per post.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "emulator/pipeline/clock.hpp"
#include "emulator/pipeline/helper_writer.hpp"

namespace gpsemu {
namespace {
namespace helper_writer_test {

struct Call {
  std::size_t first, from, to;
  UtcNs at;
  std::thread::id thread;
};

TEST(HelperWriter, WritesThePostedPartOnItsOwnThreadNotBeforeItsTime) {
  std::vector<Call> calls;  // written by the helper, read after wait_done()
  HelperWriter writer([&calls](std::size_t first, std::size_t from, std::size_t to) {
    calls.push_back({first, from, to, system_utc_now(), std::this_thread::get_id()});
  });
  for (std::size_t k = 0; k < 5; ++k) {
    const UtcNs write_at = system_utc_now() + std::chrono::milliseconds(5);
    writer.post(write_at, k, 128, 256);
    writer.wait_done();
    ASSERT_EQ(calls.size(), k + 1);
    EXPECT_EQ(calls[k].first, k);
    EXPECT_EQ(calls[k].from, 128u);
    EXPECT_EQ(calls[k].to, 256u);
    EXPECT_GE(calls[k].at, write_at) << "written before its time";
    EXPECT_NE(calls[k].thread, std::this_thread::get_id());
  }
}

TEST(HelperWriter, AWriteTimeInThePastWritesAtOnceAndDestructionFinishesThePostedEpoch) {
  std::atomic<int> writes{0};
  {
    HelperWriter writer([&writes](std::size_t, std::size_t, std::size_t) { ++writes; });
    writer.post(system_utc_now() - std::chrono::seconds(1), 0, 0, 1);
    writer.wait_done();
    EXPECT_EQ(writes.load(), 1);
    writer.post(system_utc_now() + std::chrono::milliseconds(20), 0, 0, 1);
  }  // the destructor waits for the posted epoch
  EXPECT_EQ(writes.load(), 2);
}

}  // namespace helper_writer_test
}  // namespace
}  // namespace gpsemu
