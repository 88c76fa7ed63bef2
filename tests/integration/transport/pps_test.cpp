// PPS: the pulse train arithmetic, the base class (polarity, counting), the recording fake, PPS
// specs, the GPIO backend (its start-up errors always; a real line on a gpio-sim chip or on the
// hardware named by GPSEMU_TEST_GPIOCHIP=CHIP:LINE, skipped with the reason otherwise), and the
// modem backend refusing a pseudo-terminal. Edge timing against the UTC second and ordering
// against NMEA through the runner: hw_pps_timing_test.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

#include "tests/support/scratch.hpp"
#include "tests/support/socat_pair.hpp"
#include "transport/gpio_pps.hpp"
#include "transport/modem_pps.hpp"
#include "transport/pps.hpp"
#include "transport/recording_pps.hpp"
#include "transport/serial_output.hpp"

namespace gpsemu::transport {
namespace {
namespace pps_test {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using std::chrono::seconds;

PpsTime at(std::int64_t s, std::chrono::nanoseconds sub = 0ns) { return PpsTime{seconds{s}} + sub; }

TEST(PpsTrainTest, LeadingEdgesAtWholeSecondsTrailingAfterTheWidth) {
  const auto width = 100ms;
  EXPECT_EQ(first_pps_edge_at_or_after(at(100), width), (PpsEdge{at(100), true}));
  EXPECT_EQ(first_pps_edge_at_or_after(at(100, 1ns), width), (PpsEdge{at(100, 100ms), false}));
  EXPECT_EQ(first_pps_edge_at_or_after(at(100, 100ms), width), (PpsEdge{at(100, 100ms), false}));
  EXPECT_EQ(first_pps_edge_at_or_after(at(100, 300ms), width), (PpsEdge{at(101), true}));
  PpsEdge e{at(100), true};
  const PpsEdge expected[] = {{at(100, 100ms), false}, {at(101), true}, {at(101, 100ms), false}, {at(102), true}};
  for (const auto& x : expected) {
    e = next_pps_edge(e, width);
    EXPECT_EQ(e, x);
  }
  EXPECT_EQ(next_pps_edge(PpsEdge{at(5, 900ms), false}, 900ms), (PpsEdge{at(6), true}));
}

TEST(PpsLineTest, PolarityDecidesTheLevelAndEdgesAreCounted) {
  RecordingPps high(PpsPolarity::active_high);
  RecordingPps low(PpsPolarity::active_low);
  for (RecordingPps* p : {&high, &low}) {
    EXPECT_TRUE(p->set(true));
    EXPECT_TRUE(p->pulse_on());
    EXPECT_TRUE(p->set(false));
    EXPECT_FALSE(p->pulse_on());
    EXPECT_EQ(p->stats().leading_edges, 1u);
    EXPECT_EQ(p->stats().trailing_edges, 1u);
  }
  ASSERT_EQ(high.edges.size(), 2u);
  EXPECT_TRUE(high.edges[0].level);
  EXPECT_FALSE(high.edges[1].level);
  ASSERT_EQ(low.edges.size(), 2u);
  EXPECT_FALSE(low.edges[0].level);
  EXPECT_TRUE(low.edges[1].level);
}

TEST(PpsLineTest, RecordingFakeStampsEachEdgeWithTheClockAtTheCall) {
  RecordingPps pps;
  const PpsTime before = RecordingPps::now();
  pps.set(true);
  const PpsTime after = RecordingPps::now();
  ASSERT_EQ(pps.edges.size(), 1u);
  EXPECT_GE(pps.edges[0].time, before);
  EXPECT_LE(pps.edges[0].time, after);
}

TEST(PpsLineTest, FailuresAreCountedAndReported) {
  RecordingPps pps;
  pps.fail = true;
  EXPECT_FALSE(pps.set(true));
  EXPECT_FALSE(pps.set(false));
  EXPECT_EQ(pps.stats().failures, 2u);
  EXPECT_EQ(pps.stats().leading_edges, 0u);
  EXPECT_TRUE(pps.edges.empty());
}

TEST(PpsSpecTest, ValidAndInvalidSpecs) {
  EXPECT_EQ(parse_pps_spec("gpio:/dev/gpiochip0:18"), (PpsSpec{PpsSpec::Kind::gpio, "/dev/gpiochip0", "18"}));
  EXPECT_EQ(parse_pps_spec("gpio:gpiochip4:GPIO18"), (PpsSpec{PpsSpec::Kind::gpio, "gpiochip4", "GPIO18"}));
  EXPECT_EQ(parse_pps_spec("modem:RTS").modem_line, ModemLine::rts);
  EXPECT_EQ(parse_pps_spec("modem:DTR").modem_line, ModemLine::dtr);
  EXPECT_EQ(parse_pps_spec("modem:DTR").kind, PpsSpec::Kind::modem);
  EXPECT_EQ(to_string(parse_pps_spec("gpio:/dev/gpiochip0:18")), "gpio:/dev/gpiochip0:18");
  EXPECT_EQ(to_string(parse_pps_spec("modem:rts")), "modem:RTS");
  for (const std::string bad : {"", "gpio", "gpio:", "gpio:chip", "gpio::3", "gpio:chip:", "modem:", "modem:CTS",
                                "modem:DCD", "serial:RTS"}) {
    try {
      (void)parse_pps_spec(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("gpio:CHIP:LINE"), std::string::npos) << e.what();
    }
  }
}

TEST(GpioPpsTest, MissingChipIsRefusedNamingIt) {
  for (const std::string chip : {"/dev/gpiochip9", "gpiochip9", "no-such-chip-label"}) {
    try {
      GpioPps pps(chip, "3", PpsPolarity::active_high);
      ADD_FAILURE() << chip << " opened";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("gpio:" + chip + ":3"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("no GPIO chip '" + chip + "'"), std::string::npos) << e.what();
    }
  }
}

/// A simulated GPIO chip (gpio-sim through configfs), removed at the end; or why there is none.
class GpioSim {
 public:
  static std::optional<GpioSim> create(std::string& why_not) {
    const fs::path root = "/sys/kernel/config/gpio-sim";
    if (!fs::exists(root)) {
      why_not = "no gpio-sim: /sys/kernel/config/gpio-sim does not exist (kernel without CONFIG_GPIO_SIM "
                "and CONFIGFS_FS, or configfs not mounted)";
      return std::nullopt;
    }
    GpioSim sim;
    sim.dir_ = root / ("gpsemu-test-" + std::to_string(::getpid()));
    std::error_code ec;
    if (!fs::create_directory(sim.dir_, ec) || !fs::create_directory(sim.dir_ / "bank0", ec)) {
      why_not = "cannot create a gpio-sim device in configfs: " + ec.message();
      return std::nullopt;
    }
    sim.created_ = true;
    std::ofstream(sim.dir_ / "bank0" / "num_lines") << "8\n";
    std::ofstream(sim.dir_ / "live") << "1\n";
    std::ifstream(sim.dir_ / "bank0" / "chip_name") >> sim.chip_name_;
    std::ifstream(sim.dir_ / "dev_name") >> sim.dev_name_;
    if (sim.chip_name_.empty() || !fs::exists("/dev/" + sim.chip_name_)) {
      why_not = "gpio-sim device did not come up";
      return std::nullopt;
    }
    return sim;
  }
  GpioSim(GpioSim&& o) noexcept
      : dir_(std::move(o.dir_)), chip_name_(std::move(o.chip_name_)), dev_name_(std::move(o.dev_name_)),
        created_(o.created_) {
    o.created_ = false;
  }
  ~GpioSim() {
    if (!created_) return;
    std::ofstream(dir_ / "live") << "0\n";
    std::error_code ec;
    fs::remove(dir_ / "bank0", ec);
    fs::remove(dir_, ec);
  }
  [[nodiscard]] std::string chip() const { return "/dev/" + chip_name_; }
  /// The level the line is driven to, as gpio-sim shows it.
  [[nodiscard]] int value(int line) const {
    int v = -1;
    std::ifstream(fs::path("/sys/devices/platform") / dev_name_ / chip_name_ / ("sim_gpio" + std::to_string(line)) /
                  "value") >> v;
    return v;
  }

 private:
  GpioSim() = default;
  fs::path dir_;
  std::string chip_name_, dev_name_;
  bool created_ = false;
};

TEST(GpioPpsTest, DrivesARealLineOnASimulatedChip) {
  std::string why_not;
  auto sim = GpioSim::create(why_not);
  if (!sim) GTEST_SKIP() << "no GPIO chip to test against: " << why_not;
  {
    GpioPps pps(sim->chip(), "3", PpsPolarity::active_high);
    EXPECT_EQ(sim->value(3), 0);
    ASSERT_TRUE(pps.set(true));
    EXPECT_EQ(sim->value(3), 1);
    ASSERT_TRUE(pps.set(false));
    EXPECT_EQ(sim->value(3), 0);
    try {
      GpioPps second(sim->chip(), "3", PpsPolarity::active_high);
      ADD_FAILURE() << "the line was requested twice";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("in use by 'gpsemu-pps'"), std::string::npos) << e.what();
    }
    try {
      GpioPps beyond(sim->chip(), "8", PpsPolarity::active_high);
      ADD_FAILURE() << "line 8 of 8 opened";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("has 8 lines"), std::string::npos) << e.what();
    }
  }
  GpioPps low(sim->chip(), "5", PpsPolarity::active_low);
  EXPECT_EQ(sim->value(5), 1);
  ASSERT_TRUE(low.set(true));
  EXPECT_EQ(sim->value(5), 0);
}

TEST(GpioPpsTest, DrivesTheHardwareLineNamedByTheEnvironment) {
  const char* env = std::getenv("GPSEMU_TEST_GPIOCHIP");
  if (env == nullptr) {
    GTEST_SKIP() << "set GPSEMU_TEST_GPIOCHIP=CHIP:LINE (a free output line) to test a hardware GPIO line";
  }
  const std::string text = env;
  const auto colon = text.rfind(':');
  ASSERT_NE(colon, std::string::npos) << "GPSEMU_TEST_GPIOCHIP must be CHIP:LINE";
  GpioPps pps(text.substr(0, colon), text.substr(colon + 1), PpsPolarity::active_high);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(pps.set(true));
    EXPECT_TRUE(pps.set(false));
  }
  EXPECT_EQ(pps.stats().failures, 0u);
  EXPECT_THROW(GpioPps(text.substr(0, colon), text.substr(colon + 1), PpsPolarity::active_high), std::runtime_error);
}

TEST(ModemPpsTest, PseudoTerminalIsRefusedAtStartUp) {
  ASSERT_FALSE(test::socat_path().empty()) << "socat is needed: tools/setup --with-test-deps installs it";
  std::string templ = (test::scratch_root() / "gpsemu_pps_XXXXXX").string();
  ASSERT_NE(::mkdtemp(templ.data()), nullptr);
  const fs::path dir = templ;
  {
    test::SocatPair pair(dir / "A", dir / "B");
    SerialOutput serial(SerialTarget{pair.a(), std::nullopt}, SerialOptions{});
    for (const ModemLine line : {ModemLine::rts, ModemLine::dtr}) {
      try {
        ModemPps pps(serial, line, PpsPolarity::active_high);
        ADD_FAILURE() << "a pty carried PPS";
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(std::string("no ") + to_string(line) + " modem control line"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("pseudo-terminal"), std::string::npos) << e.what();
      }
    }
  }
  fs::remove_all(dir);
}

}  // namespace pps_test
}  // namespace
}  // namespace gpsemu::transport
