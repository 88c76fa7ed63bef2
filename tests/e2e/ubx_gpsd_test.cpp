// gpsemu as a u-blox (--protocol ubx) against the real gpsd, read-write (no -b), and ubxtool
// (gpsd-clients) through that gpsd: gpsd recognises the u-blox driver from the UBX stream and
// its MON-VER answer, reports 3-D fixes at the truth, and ubxtool's polls and writes are answered.
// gpsd or ubxtool missing is a failure, not a skip. Waits are poll() with timeouts.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/model/time.hpp"
#include "tests/support/gpsd.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono;
using nlohmann::json;

constexpr const char* kUbxtool = "/usr/bin/ubxtool";
constexpr double kOriginLat = 43.0725, kOriginLon = -89.4125;  // gpsemu's default origin

struct Tpv {
  int mode = 0;
  std::optional<std::int64_t> time_of_day_ms;
  double lat_deg = NAN, lon_deg = NAN;
};

std::int64_t ms_of_day(const std::string& iso) {
  const auto t = parse_iso8601_utc(iso);
  return duration_cast<milliseconds>(t - floor<days>(t)).count();
}

/// gpsemu --protocol ubx on a pty, gpsd (read-write) on it, and a watching client.
class UbxGpsd {
 public:
  UbxGpsd(const std::string& name, const std::vector<std::string>& args, double duration_s)
      : dir_(test::scratch_dir("ubx_gpsd", name)) {
    const fs::path link = dir_ / "gps";
    std::vector<std::string> argv{GPSEMU_BINARY, "--protocol", "ubx", "--output", "pty:" + link.string(),
                                  "--duration", fmt::format("{}", duration_s), "--log-level", "info"};
    argv.insert(argv.end(), args.begin(), args.end());
    gpsemu_.emplace(argv);
    if (!gpsemu_->wait_for_stderr("UBX on", seconds(20))) throw std::runtime_error("gpsemu did not start: " + gpsemu_->stderr_text());
    port_ = test::free_tcp_port();
    gpsd_.emplace(std::vector<std::string>{test::kGpsd, "-N", "-n", "-S", std::to_string(port_), fs::read_symlink(link).string()});
    sock_ = test::connect_gpsd(port_, seconds(10));
    if (sock_ < 0) throw std::runtime_error("gpsd does not listen: " + gpsd_->stderr_text());
    const std::string watch = "?WATCH={\"enable\":true,\"json\":true};\n";
    if (::write(sock_, watch.data(), watch.size()) != static_cast<ssize_t>(watch.size())) throw std::runtime_error("watch");
  }
  ~UbxGpsd() {
    if (sock_ >= 0) ::close(sock_);
    gpsemu_->signal(SIGTERM);
    gpsemu_->wait(seconds(10));
    gpsd_->signal(SIGTERM);
    gpsd_->wait(seconds(10));
    fs::remove_all(dir_);
  }

  /// Reads gpsd's reports for `how_long` (or until `until` says stop), collecting TPVs and the driver.
  template <class Until>
  void read_reports(milliseconds how_long, Until until) {
    test::read_with_deadline(sock_, {how_long}, [&](std::string_view chunk) {
      buffer_.append(chunk);
      std::size_t nl;
      while ((nl = buffer_.find('\n')) != std::string::npos) {
        const json j = json::parse(buffer_.substr(0, nl), nullptr, false);
        buffer_.erase(0, nl + 1);
        if (j.is_discarded() || !j.contains("class")) continue;
        if (j["class"] == "DEVICE" && j.contains("driver")) driver = j["driver"].get<std::string>();
        if (j["class"] == "DEVICES") {
          for (const auto& d : j.value("devices", json::array())) {
            if (d.contains("driver")) driver = d["driver"].get<std::string>();
          }
        }
        if (j["class"] != "TPV") continue;
        Tpv r;
        r.mode = j.value("mode", 0);
        if (j.contains("time")) r.time_of_day_ms = ms_of_day(j["time"].get<std::string>());
        r.lat_deg = j.value("lat", std::numeric_limits<double>::quiet_NaN());
        r.lon_deg = j.value("lon", std::numeric_limits<double>::quiet_NaN());
        tpv.push_back(r);
      }
      return until();
    });
  }
  void read_reports(milliseconds how_long) {
    read_reports(how_long, [] { return false; });
  }

  /// ubxtool through this gpsd: its output.
  std::string ubxtool(const std::vector<std::string>& args) {
    std::vector<std::string> argv{kUbxtool};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.push_back(fmt::format("127.0.0.1:{}", port_));
    test::Process p(argv);
    EXPECT_EQ(p.wait(seconds(20)), 0) << p.stderr_text();
    return p.stdout_text();
  }

  std::string driver;
  std::vector<Tpv> tpv;

 private:
  fs::path dir_;
  std::optional<test::Process> gpsemu_, gpsd_;
  int port_ = 0;
  int sock_ = -1;
  std::string buffer_;
};

bool tools_present() {
  if (::access(test::kGpsd, X_OK) != 0 || ::access(kUbxtool, X_OK) != 0) {
    ADD_FAILURE() << "gpsd or ubxtool is missing: tools/setup --with-test-deps installs them (gpsd, gpsd-clients)";
    return false;
  }
  return true;
}

/// Distinct mode-3 TPV times from the first one on (the last `drop_last` left out), and the worst
/// distance from the truth in degrees.
struct Mode3 {
  std::set<std::int64_t> times;
  double worst_deg = 0.0;
};
Mode3 mode3_of(const std::vector<Tpv>& tpv) {
  Mode3 m;
  for (const Tpv& r : tpv) {
    if (r.mode != 3 || !r.time_of_day_ms) continue;
    m.times.insert(*r.time_of_day_ms);
    m.worst_deg = std::max({m.worst_deg, std::fabs(r.lat_deg - kOriginLat), std::fabs(r.lon_deg - kOriginLon)});
  }
  return m;
}

TEST(UbxGpsd, DeviceIsUbloxAndTpvIsMode3AtTheTruthFor99PercentOfEpochsAt5Hz) {
  if (!tools_present()) return;
  UbxGpsd run("mode3", {"--noise", "none", "--rate", "5", "--receiver", "ublox-m8n"}, 14.0);
  run.read_reports(seconds(12));
  EXPECT_EQ(run.driver, "u-blox");
  const Mode3 m = mode3_of(run.tpv);
  ASSERT_GE(m.times.size(), 2u) << "gpsd reported no 3-D fixes";
  const std::int64_t first = *m.times.begin(), last = *m.times.rbegin();
  const auto epochs = static_cast<double>((last - first) / 200 + 1);
  const double fraction = static_cast<double>(m.times.size()) / epochs;
  std::cout << fmt::format("gpsd (u-blox driver '{}'): mode 3 for {} of {} epochs at 5 Hz since its first fix "
                           "({:.2f}%), worst distance from the truth {:.1e} deg\n",
                           run.driver, m.times.size(), epochs, 100.0 * fraction, m.worst_deg);
  EXPECT_GE(epochs, 40);
  EXPECT_GE(fraction, 0.99);
  EXPECT_LE(m.worst_deg, 2e-7) << "NAV-PVT carries 1e-7 deg";
  for (const std::int64_t t : m.times) EXPECT_EQ(t % 200, 0) << "a time off the 5 Hz grid";
}

TEST(UbxGpsd, UbxtoolThroughGpsdPollsMonVerAndCfgRate) {
  if (!tools_present()) return;
  UbxGpsd run("ubxtool", {"--noise", "none", "--rate", "5", "--receiver", "ublox-f9p"}, 30.0);
  run.read_reports(seconds(10), [&] { return run.driver == "u-blox"; });
  ASSERT_EQ(run.driver, "u-blox");
  const std::string mon_ver = run.ubxtool({"-p", "MON-VER", "-P", "27.31", "-w", "1"});
  EXPECT_NE(mon_ver.find("UBX-MON-VER:"), std::string::npos) << mon_ver;
  EXPECT_NE(mon_ver.find("MOD=ZED-F9P"), std::string::npos) << mon_ver;
  EXPECT_NE(mon_ver.find("PROTVER=27.31"), std::string::npos) << mon_ver;
  const std::string rate = run.ubxtool({"-p", "CFG-RATE", "-P", "27.31", "-w", "1"});
  EXPECT_NE(rate.find("measRate 200 navRate 1"), std::string::npos) << rate;
  EXPECT_NE(rate.find("ACK to Class x06 (CFG) ID x08 (RATE)"), std::string::npos) << rate;
}

// A raw CFG-RATE write (measRate 400 ms) is acknowledged and the solutions follow it: gpsd's
// TPVs come every 400 ms from then on, on the 400 ms grid.
TEST(UbxGpsd, RawCfgRateWriteIsAcknowledgedAndTheEpochRateFollows) {
  if (!tools_present()) return;
  UbxGpsd run("rate", {"--noise", "none", "--rate", "5", "--receiver", "ublox-m8n"}, 30.0);
  run.read_reports(seconds(10), [&] { return run.driver == "u-blox"; });
  ASSERT_EQ(run.driver, "u-blox");
  const std::string ack = run.ubxtool({"-c", "0x06,0x08,0x90,0x01,0x01,0x00,0x01,0x00", "-P", "18", "-w", "1"});
  EXPECT_NE(ack.find("ACK to Class x06 (CFG) ID x08 (RATE)"), std::string::npos) << ack;
  run.tpv.clear();
  run.read_reports(seconds(5));
  const Mode3 m = mode3_of(run.tpv);
  ASSERT_GE(m.times.size(), 8u);
  // What gpsd sent while ubxtool ran is read too: the solutions on the 200 ms grid end there.
  std::vector<std::int64_t> after;
  for (const std::int64_t t : m.times) {
    if (t % 400 != 0) after.clear();
    else after.push_back(t);
  }
  ASSERT_GE(after.size(), 10u) << "5 s at 400 ms";
  const auto expected = static_cast<std::size_t>((after.back() - after.front()) / 400 + 1);
  std::cout << fmt::format("after CFG-RATE 400 ms: {} solutions on the 400 ms grid of {} expected, {} before on the "
                           "200 ms grid\n", after.size(), expected, m.times.size() - after.size());
  EXPECT_GE(static_cast<double>(after.size()), 0.95 * static_cast<double>(expected)) << "solutions missing";
}

}  // namespace
}  // namespace gpsemu
