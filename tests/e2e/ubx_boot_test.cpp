// A drone boots as PX4 boots its u-blox (PX4-GPSDrivers src/ubx.cpp, GPSDriverUBX::configure(),
// read for its order and timeouts; the frames are written here): 20 boots against gpsemu binaries
// at --rate 1 given only --receiver (the factory state: NMEA at 1 Hz, UBX answered), each opening
// the pty at another phase of the second (spread over the whole second, jittered), configuring
// with the auto-baud probe (a first CFG-VALSET, 2 s for its ACK) then the VALSET path (F9P, M9N)
// or, when that VALSET is NAKed, the legacy CFG-PRT path (M8N), waiting 250 ms for each ACK PX4
// requires, then waiting as PX4's GPS task does (500 ms) for the first NAV-PVT of the new 5 Hz
// rate. A configuration that would have made PX4 retry (a required ACK missing, or no NAV-PVT
// within 500 ms) is counted: none of 20 may. Before a boot the receiver is power-cycled with
// CFG-RST (a hardware reset: RAM reloaded from the layers, here the defaults). Four receivers
// boot in parallel, five times each, to keep the run short. An M10 boots three times on its own
// (the VALSET path only).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <deque>
#include <future>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"

namespace gpsemu {
namespace {
namespace ubx_boot_test {

using namespace std::chrono;
using ubx::MessageId;

constexpr milliseconds kConfigTimeout{250};   // PX4 UBX_CONFIG_TIMEOUT
constexpr milliseconds kFirstValsetWait{2000};  // PX4 waits longer for the probe (an M10 at 9600 baud)
constexpr milliseconds kReceiveTimeout{500};  // PX4 gps.cpp: no position within this, the driver restarts
constexpr int kBootsPerReceiver = 5;

struct KeyValue {
  std::uint32_t key;
  std::uint64_t value;
};

std::string valset(std::initializer_list<KeyValue> items) {
  std::string p;
  ubx::put_u1(p, 0);     // version
  ubx::put_u1(p, 0x01);  // RAM, as PX4
  ubx::put_zeros(p, 2);
  for (const KeyValue& kv : items) {
    ubx::put_u4(p, kv.key);
    ubx::put_le(p, kv.value, static_cast<int>(ubx::key_value_bytes(kv.key)));
  }
  return ubx::frame_bytes(ubx::msg::cfg_valset, p);
}

/// PX4's two CFG-PRT blocks (UART1 and USB): UBX (+RTCM3) in, UBX out.
std::string cfg_prt_pair(std::uint32_t baud) {
  std::string p;
  for (const std::uint8_t port : {1, 3}) {
    ubx::put_u1(p, port);
    ubx::put_zeros(p, 3);
    ubx::put_u4(p, 0x08D0);
    ubx::put_u4(p, baud);
    ubx::put_u2(p, 0x0021);
    ubx::put_u2(p, 0x0001);
    ubx::put_zeros(p, 4);
  }
  return ubx::frame_bytes(ubx::msg::cfg_prt, p);
}

std::string cfg_msg(MessageId id, std::uint8_t rate) {
  return ubx::frame_bytes(ubx::msg::cfg_msg, std::string{static_cast<char>(id.msg_class), static_cast<char>(id.msg_id),
                                                         static_cast<char>(rate)});
}

/// The driver's side of the pty: what it waits for, as PX4's waitForAck() and receive() do.
class Driver {
 public:
  explicit Driver(int fd) : fd_(fd) {}

  void send(const std::string& bytes) { ASSERT_EQ(::write(fd_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size())); }

  /// 1: ACK-ACK of `id` (or, for MON-VER, its answer), 0: ACK-NAK, -1: nothing within `timeout`.
  int wait_for_ack(MessageId id, milliseconds timeout) {
    const auto found = wait_until(timeout, [&](const ubx::Frame& f) {
      if (id == ubx::msg::mon_ver) return f.id == ubx::msg::mon_ver;
      return (f.id == ubx::msg::ack_ack || f.id == ubx::msg::ack_nak) && f.payload.size() == 2 &&
             static_cast<std::uint8_t>(f.payload[0]) == id.msg_class && static_cast<std::uint8_t>(f.payload[1]) == id.msg_id;
    });
    if (!found) return -1;
    last_answer_ = found->second;
    return found->first.id == ubx::msg::ack_nak ? 0 : 1;
  }

  /// The NAV-PVT frame that came within `timeout`, and when.
  std::optional<std::pair<ubx::Frame, steady_clock::time_point>> wait_for_pvt(milliseconds timeout) {
    return wait_until(timeout, [](const ubx::Frame& f) { return f.id == ubx::msg::nav_pvt; });
  }

  [[nodiscard]] steady_clock::time_point last_answer() const { return last_answer_; }

 private:
  template <class Wanted>
  std::optional<std::pair<ubx::Frame, steady_clock::time_point>> wait_until(milliseconds timeout, Wanted wanted) {
    const auto deadline = steady_clock::now() + timeout;
    while (true) {
      while (!pending_.empty()) {
        auto [frame, at] = std::move(pending_.front());
        pending_.pop_front();
        if (wanted(frame)) return std::pair{std::move(frame), at};
      }
      const auto left = duration_cast<milliseconds>(deadline - steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      (void)test::read_with_deadline(fd_, {left}, [&](std::string_view bytes) {
        const auto now = steady_clock::now();
        for (auto& m : reader_.feed(bytes)) {
          if (auto* f = std::get_if<ubx::Frame>(&m)) pending_.emplace_back(std::move(*f), now);
        }
        return !pending_.empty();
      });
    }
  }

  int fd_;
  ubx::FrameReader reader_;
  std::deque<std::pair<ubx::Frame, steady_clock::time_point>> pending_;
  steady_clock::time_point last_answer_{};
};

struct Boot {
  bool retry = false;        ///< PX4 would have configured again
  std::string why;           ///< what made it retry
  milliseconds to_first_pvt{};  ///< last ACK to the first NAV-PVT
  std::uint32_t pvt_spacing_ms = 0;  ///< iTOW of the second NAV-PVT minus the first's
  bool legacy = false;       ///< the VALSET probe was NAKed: the CFG-PRT path
};

/// One PX4 configure() and its first receive().
Boot px4_boot(int fd) {
  Driver d(fd);
  Boot boot;
  auto require = [&](MessageId id, milliseconds timeout, const char* what) {
    if (boot.retry) return;
    if (d.wait_for_ack(id, timeout) != 1) {
      boot.retry = true;
      boot.why = what;
    }
  };
  // Auto-baud probe at the first baud PX4 tries (a pty takes any): UART1 8N1, UBX only.
  d.send(valset({{0x20520002, 1}, {0x20520003, 0}, {0x20520004, 0}, {ubx::key::uart1inprot_ubx, 1}, {0x10730002, 0},
                 {ubx::key::uart1outprot_ubx, 1}, {ubx::key::uart1outprot_nmea, 0}}));
  const int probe = d.wait_for_ack(ubx::msg::cfg_valset, kFirstValsetWait);
  if (probe == 1) {
    d.send(valset({{ubx::key::uart1_baudrate, 115200}}));
    (void)d.wait_for_ack(ubx::msg::cfg_valset, kConfigTimeout);  // no ACK required
    d.send(ubx::frame_bytes(ubx::msg::mon_ver, {}));
    require(ubx::msg::mon_ver, kConfigTimeout, "MON-VER");
    d.send(valset({{0x10730004, 1}, {0x10770001, 1}, {0x10770004, 1}, {0x10770002, 0}, {0x10780001, 1}, {0x10780002, 0}}));
    require(ubx::msg::cfg_valset, kConfigTimeout, "VALSET USB protocols");
    d.send(valset({{ubx::key::navspg_fixmode, 3}, {0x2011001C, 3}, {ubx::key::navspg_dynmodel, 8}, {0x10220001, 0},
                   {0x10220002, 0}, {0x10220003, 0}, {0x10220004, 0}, {ubx::key::rate_meas, 200}, {ubx::key::rate_nav, 1},
                   {ubx::key::rate_timeref, 0}}));
    require(ubx::msg::cfg_valset, kConfigTimeout, "VALSET navigation and rate");
    d.send(valset({{0x20140011, 3}}));  // RTK fixed (not required)
    (void)d.wait_for_ack(ubx::msg::cfg_valset, kConfigTimeout);
    d.send(valset({{0x20910007, 1}, {0x20910039, 1}, {0x2091001B, 1}, {0x20910016, 10}}));  // PVT, DOP, STATUS, SAT on UART1
    require(ubx::msg::cfg_valset, kConfigTimeout, "VALSET message rates");
  } else if (probe == 0) {
    boot.legacy = true;
    d.send(cfg_prt_pair(38400));
    require(ubx::msg::cfg_prt, kConfigTimeout, "CFG-PRT");
    d.send(cfg_prt_pair(115200));
    (void)d.wait_for_ack(ubx::msg::cfg_prt, kConfigTimeout);
    d.send(ubx::frame_bytes(ubx::msg::mon_ver, {}));
    require(ubx::msg::mon_ver, kConfigTimeout, "MON-VER");
    std::string rate;
    ubx::put_u2(rate, 200);
    ubx::put_u2(rate, 1);
    ubx::put_u2(rate, 0);
    d.send(ubx::frame_bytes(ubx::msg::cfg_rate, rate));
    require(ubx::msg::cfg_rate, kConfigTimeout, "CFG-RATE");
    for (const MessageId id : {ubx::msg::nav_pvt, ubx::msg::nav_dop, ubx::msg::nav_status}) {
      d.send(cfg_msg(id, 1));
      require(ubx::msg::cfg_msg, kConfigTimeout, "CFG-MSG");
    }
  } else {
    boot.retry = true;
    boot.why = "no answer to the VALSET probe";
  }
  if (boot.retry) return boot;
  const auto first = d.wait_for_pvt(kReceiveTimeout);
  if (!first) {
    boot.retry = true;
    boot.why = "no NAV-PVT within 500 ms of the configuration";
    return boot;
  }
  boot.to_first_pvt = duration_cast<milliseconds>(first->second - d.last_answer());
  if (const auto second = d.wait_for_pvt(kReceiveTimeout)) {
    boot.pvt_spacing_ms = ubx::get_u4(second->first.payload, 0) - ubx::get_u4(first->first.payload, 0);
  }
  return boot;
}

/// CFG-RST: hardware reset, hot start (navigation data kept): RAM reloads from the layers.
std::string power_cycle() {
  std::string p;
  ubx::put_u2(p, 0x0000);
  ubx::put_u1(p, 0x00);
  ubx::put_u1(p, 0);
  return ubx::frame_bytes(ubx::msg::cfg_rst, p);
}

/// Boots one receiver `phases.size()` times, each at its phase of the second (seconds).
std::vector<Boot> boot_receiver(const std::string& model, std::size_t index, const std::vector<double>& phases) {
  const auto dir = test::scratch_dir("ubx_boot", fmt::format("{}-{}", model, index));
  const auto link = dir / "gps";
  test::Process gpsemu({GPSEMU_BINARY, "--receiver", model, "--rate", "1", "--noise", "none", "--output",
                        "pty:" + link.string(), "--duration", "30", "--log-level", "warn"});
  std::vector<Boot> boots;
  // The pty exists once the process is up; retry the open for a few seconds.
  for (int i = 0; i < 100 && ::access(link.c_str(), F_OK) != 0; ++i) std::this_thread::sleep_for(50ms);
  for (const double phase : phases) {
    const auto now = system_clock::now().time_since_epoch();
    const auto into = now % seconds{1};
    auto wait = duration_cast<nanoseconds>(duration<double>(phase)) - into;
    if (wait < 0ns) wait += seconds{1};
    std::this_thread::sleep_for(wait);
    const int fd = test::open_raw(link);
    boots.push_back(px4_boot(fd));
    const std::string reset = power_cycle();
    if (::write(fd, reset.data(), reset.size()) != static_cast<ssize_t>(reset.size())) ADD_FAILURE() << "CFG-RST not written";
    ::close(fd);
  }
  gpsemu.signal(SIGTERM);
  (void)gpsemu.wait(seconds(10));
  return boots;
}

TEST(UbxBoot, Px4ConfiguresAFactoryStateReceiverWithoutARetryAtAnyPhaseOfTheSecond) {
  const std::vector<std::string> models = {"ublox-f9p", "ublox-m9n", "ublox-m8n", "ublox-m8n"};
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> jitter(0.0, 1.0);
  std::vector<std::vector<double>> phases(models.size());
  const int boots = kBootsPerReceiver * static_cast<int>(models.size());
  for (int k = 0; k < boots; ++k) {
    phases[static_cast<std::size_t>(k) % models.size()].push_back((k + jitter(rng)) / boots);
  }
  std::vector<std::future<std::vector<Boot>>> runs;
  for (std::size_t r = 0; r < models.size(); ++r) runs.push_back(std::async(std::launch::async, boot_receiver, models[r], r, phases[r]));
  int retries = 0, legacy = 0, total = 0;
  milliseconds worst{0};
  for (std::size_t r = 0; r < models.size(); ++r) {
    const std::vector<Boot> got = runs[r].get();
    ASSERT_EQ(got.size(), phases[r].size());
    for (std::size_t i = 0; i < got.size(); ++i) {
      const Boot& b = got[i];
      ++total;
      legacy += b.legacy ? 1 : 0;
      if (b.retry) {
        ++retries;
        ADD_FAILURE() << models[r] << " boot at phase " << phases[r][i] << " s: PX4 would retry: " << b.why;
        continue;
      }
      worst = std::max(worst, b.to_first_pvt);
      EXPECT_EQ(b.pvt_spacing_ms, 200u) << models[r] << " at phase " << phases[r][i] << ": 5 Hz from the first solution";
      EXPECT_EQ(b.legacy, models[r] == "ublox-m8n") << models[r];
    }
  }
  EXPECT_EQ(total, boots);
  EXPECT_EQ(retries, 0) << retries << " of " << total << " configurations needed a retry";
  EXPECT_EQ(legacy, 2 * kBootsPerReceiver);
  // The new rate at once: the first 5 Hz solution within one new period (200 ms) and the latency
  // (50 ms) of the last ACK, with 100 ms for a loaded machine (the old grid gave up to 1 s).
  EXPECT_LE(worst, milliseconds{350});
  RecordProperty("worst_ack_to_first_pvt_ms", static_cast<int>(worst.count()));
  std::printf("%d boots, %d retries, %d on the legacy path; worst last ACK to first NAV-PVT: %lld ms\n", total,
              retries, legacy, static_cast<long long>(worst.count()));
}

TEST(UbxBoot, Px4ConfiguresAnM10OnTheValsetPath) {
  // --receiver ublox-m10: PX4's probe VALSET is ACKed (an M10 has no legacy CFG-PRT path), every
  // required VALSET too (its RTCM3 input key included), and 5 Hz NAV-PVT follows.
  const std::vector<double> phases = {0.1, 0.45, 0.8};
  const std::vector<Boot> got = boot_receiver("ublox-m10", 9, phases);
  ASSERT_EQ(got.size(), phases.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_FALSE(got[i].retry) << "phase " << phases[i] << " s: PX4 would retry: " << got[i].why;
    EXPECT_FALSE(got[i].legacy);
    if (!got[i].retry) {
      EXPECT_EQ(got[i].pvt_spacing_ms, 200u) << "phase " << phases[i];
    }
  }
}

}  // namespace ubx_boot_test
}  // namespace
}  // namespace gpsemu
