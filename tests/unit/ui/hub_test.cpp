// ui::Hub (emulator/ui/hub.hpp) between the loop and its watchers, without a server: nothing is
// rendered while nobody watches; a page that watches gets each epoch's JSON (the fix, the truth,
// the error against it, the satellites) and waits for the next one; a fault request from another
// thread is answered by the loop's service() with the control socket's protocol and acts at the
// next epoch; after close() waiting pages are woken and requests refused. And --ui's spec.
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <memory>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "emulator/pipeline/channel_set.hpp"
#include "emulator/ui/hub.hpp"
#include "emulator/ui/ui_spec.hpp"

namespace gpsemu {
namespace {
namespace hub_test {

using namespace std::chrono_literals;
using nlohmann::json;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T12:00:00Z");

/// Two metres east of the origin, still.
class EastSource final : public sources::PoseSource {
 public:
  std::optional<sources::Truth> truth_at(UtcNs) override {
    sources::Truth t{};
    t.position_m = {2.0, 0.0, 0.0};
    return t;
  }
  [[nodiscard]] std::string describe() const override { return "east"; }
};

struct Fixture {
  Timeline timeline{EpochGrid(10.0), EpochGrid(10.0).index_at_or_after(kT0), 0ns};
  ChannelSet set{timeline, std::nullopt};
  std::unique_ptr<ui::Hub> hub;
  UtcNs t{};

  Fixture() {
    ChannelSettings s;
    s.origin = {43.0725, -89.4125, 260.0};
    auto ch = std::make_unique<Channel>(s, kT0);
    ch->set_source(std::make_unique<EastSource>());
    set.add(std::move(ch));
    hub = std::make_unique<ui::Hub>(set, 0ns);
    set.set_observer(hub.get());
  }
  void epoch() {
    ASSERT_TRUE(set.next_epoch(t));
    (void)set.produce(0, t);
  }
};

TEST(UiHub, NothingIsPublishedWhileNobodyWatches) {
  Fixture f;
  f.epoch();
  EXPECT_EQ(f.hub->wait_after(0, 0, 0ms).json, nullptr);
  f.hub->watch(0, +1);
  f.epoch();
  const ui::Hub::Published p = f.hub->wait_after(0, 0, 0ms);
  ASSERT_NE(p.json, nullptr);
  EXPECT_EQ(p.epoch, 2u);
}

TEST(UiHub, AWatchingPageGetsEachEpochWithTheErrorAgainstTheTruth) {
  Fixture f;
  f.hub->watch(0, +1);
  f.epoch();
  const ui::Hub::Published first = f.hub->wait_after(0, 0, 0ms);
  ASSERT_NE(first.json, nullptr);
  const json e = json::parse(*first.json);
  EXPECT_EQ(e["class"], "EPOCH");
  EXPECT_EQ(e["receiver"], 0);
  EXPECT_EQ(e["time"], "2024-05-01T12:00:00.000Z");
  EXPECT_DOUBLE_EQ(e["truth"]["east_m"].get<double>(), 2.0);
  ASSERT_TRUE(e["fix"]["quality"].get<int>() >= 1) << e.dump();
  // The error is reported minus truth, in the same frame.
  EXPECT_NEAR(e["error"]["east_m"].get<double>(), e["reported"]["east_m"].get<double>() - 2.0, 0.002);
  EXPECT_NEAR(e["error"]["horizontal_m"].get<double>(),
              std::hypot(e["error"]["east_m"].get<double>(), e["error"]["north_m"].get<double>()), 0.002);
  EXPECT_EQ(e["satellites"].size(), e["fix"]["satellites_in_view"].get<std::size_t>());
  EXPECT_TRUE(e["ubx"].is_null());
  EXPECT_EQ(e["faults"].size(), 0u);

  // A page waiting for the next epoch gets it when the loop makes it.
  auto next = std::async(std::launch::async, [&] { return f.hub->wait_after(0, first.epoch, 10s); });
  f.epoch();
  const ui::Hub::Published second = next.get();
  ASSERT_NE(second.json, nullptr);
  EXPECT_EQ(second.epoch, first.epoch + 1);
  EXPECT_EQ(json::parse(*second.json)["time"], "2024-05-01T12:00:00.100Z");
}

TEST(UiHub, AFaultRequestIsAnsweredByTheLoopAndActsAtTheNextEpoch) {
  Fixture f;
  f.hub->watch(0, +1);
  f.epoch();
  auto answer = std::async(std::launch::async, [&] { return f.hub->request(R"({"fault":"outage","duration":1})", 10s); });
  // The loop services its inputs between epochs.
  while (answer.wait_for(1ms) != std::future_status::ready) f.hub->service();
  const std::optional<std::string> a = answer.get();
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(json::parse(*a)["class"], "FAULT") << *a;
  f.epoch();
  const json e = json::parse(*f.hub->wait_after(0, 0, 0ms).json);
  EXPECT_EQ(e["fix"]["quality"], 0) << "an outage: no fix";
  ASSERT_EQ(e["faults"].size(), 1u);
  EXPECT_EQ(e["faults"][0]["fault"], "outage");
  EXPECT_TRUE(e["faults"][0]["active"].get<bool>());
  EXPECT_NEAR(e["faults"][0]["remaining_s"].get<double>(), 1.0, 0.11);
  EXPECT_TRUE(e["error"].is_null()) << "no fix, no error";
  // ctl status's additions.
  const json extra = json::parse(f.hub->status_extra(0));
  EXPECT_TRUE(extra["error_horizontal_m"].is_null());
  EXPECT_EQ(extra["page_clients"], 1);
}

TEST(UiHub, AfterCloseWaitingPagesWakeAndRequestsAreRefused) {
  Fixture f;
  f.hub->watch(0, +1);
  auto waiting = std::async(std::launch::async, [&] { return f.hub->wait_after(0, 0, 60s); });
  std::this_thread::sleep_for(10ms);
  f.hub->close();
  EXPECT_EQ(waiting.wait_for(10s), std::future_status::ready);
  EXPECT_EQ(waiting.get().json, nullptr);
  EXPECT_FALSE(f.hub->request(R"({"status":true})", 1s).has_value());
}

TEST(UiSpec, HostDefaultsToLoopbackAndBadSpecsAreNamed) {
  EXPECT_EQ(ui::parse_ui_spec("8080").host, "127.0.0.1");
  EXPECT_EQ(ui::parse_ui_spec("8080").port, 8080);
  EXPECT_EQ(ui::parse_ui_spec("0.0.0.0:0").host, "0.0.0.0");
  EXPECT_EQ(ui::parse_ui_spec("[::1]:81").host, "::1");
  for (const char* bad : {"", "http", "65536", ":80", "1.2.3.4:x"}) {
    try {
      (void)ui::parse_ui_spec(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("ui:"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(ui::is_loopback("127.0.0.1"));
  EXPECT_TRUE(ui::is_loopback("::1"));
  EXPECT_TRUE(ui::is_loopback("localhost"));
  EXPECT_FALSE(ui::is_loopback("0.0.0.0"));
  EXPECT_FALSE(ui::is_loopback("192.168.1.2"));
}

}  // namespace hub_test
}  // namespace
}  // namespace gpsemu
