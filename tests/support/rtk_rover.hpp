// Test support for the RTK end-to-end tests: the base station they send (300 m north of gpsemu's
// default origin, station 42: its 1006 and a GPS MSM7 an epoch, the project's encoder) and a u-blox
// rover (an F9P, or any model) on a pty whose client writes that base's RTCM3 into the u-blox port, as PX4 and ArduPilot
// inject corrections, and reads what the receiver answers.
#pragma once

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <GeographicLib/Geocentric.hpp>
#include <gtest/gtest.h>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "nmea/parse.hpp"
#include "tests/support/process.hpp"
#include "tests/support/pty_client.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::test {

inline constexpr double kOriginLatDeg = 43.0725, kOriginLonDeg = -89.4125;  // gpsemu's default origin

/// The base: 300 m north of the origin, 230 m high (ellipsoid), station 42, antenna 1.5 m.
inline rtk::BasePosition base_300m_north() {
  rtk::BasePosition b;
  b.station_id = 42;
  GeographicLib::Geocentric::WGS84().Forward(kOriginLatDeg + 300.0 / 111000.0, kOriginLonDeg, 230.0, b.ecef_x_m,
                                             b.ecef_y_m, b.ecef_z_m);
  b.antenna_height_m = 1.5;
  return b;
}

/// The base's 1006 frame, as a base station sends it.
/// The fix quality of each GGA written to `file`, in order.
inline std::vector<int> gga_qualities_in(const std::filesystem::path& file) {
  std::vector<int> out;
  nmea::StreamReader reader;
  for (const auto& s : reader.feed(read_file(file))) {
    if (s.type != "GGA") continue;
    const auto gga = nmea::parse_gga(s);
    if (gga.ok()) out.push_back(static_cast<int>(gga->quality));
  }
  return out;
}

inline std::string base_1006() { return rtk::rtcm3_frame_bytes(rtk::encode_base_position(base_300m_north(), true)); }

/// The base's epoch `k` (k = 0, 1, ... 100 ms apart): its 1006 and a GPS MSM7 of 10 satellites.
inline std::string base_epoch(int k) {
  return base_1006() + rtk::rtcm3_frame_bytes(rtk::encode_msm(1077, 42, 345600000u + 100u * static_cast<unsigned>(k), 10, 2));
}

/// How the rover's client talks to the port.
struct RoverClient {
  std::string setup;                    ///< written first (the messages it turns on, a VALSET)
  std::chrono::milliseconds settle{0};  ///< then this long before the corrections
  int epochs = 20;                      ///< base_epoch(0 .. epochs - 1), 100 ms apart
};

/// What the client read from the port, and gpsemu's stderr.
struct RoverRun {
  std::string bytes;
  std::string log;
};

/// gpsemu as `model` (`--receiver MODEL --protocol PROTOCOL`) at 5 Hz for `duration` on a pty,
/// with RTK converging fast (0.4 s to float, 1.0 s to fixed); `client` writes into its port and
/// reads it meanwhile. gpsemu not starting, no client or a short write is a test failure.
inline RoverRun run_rover(const std::string& model, const std::string& protocol, const std::string& name,
                          const std::string& duration, const RoverClient& client) {
  using namespace std::chrono;
  const std::filesystem::path dir = scratch_dir("rover", name);
  const std::filesystem::path link = dir / "gps";
  Process gpsemu({GPSEMU_BINARY, "--receiver", model, "--protocol", protocol, "--output", "pty:" + link.string(),
                  "--rate", "5", "--duration", duration, "--rtk-convergence", "0.4,1.0,0", "--log-level", "info"});
  RoverRun run;
  if (!gpsemu.wait_for_stderr("on /dev/pts", seconds(20))) {
    ADD_FAILURE() << "gpsemu did not start: " << gpsemu.stderr_text();
    return run;
  }
  const int fd = open_raw_pty_client(link);
  if (fd < 0) {
    ADD_FAILURE() << "cannot open the pty " << link;
    return run;
  }
  const auto drain = [&] {
    char buf[4096];
    ssize_t n;
    while ((n = ::read(fd, buf, sizeof buf)) > 0) run.bytes.append(buf, static_cast<std::size_t>(n));
  };
  const auto write_all = [fd](const std::string& bytes) {
    EXPECT_EQ(::write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  };
  write_all(client.setup);
  if (client.settle.count() > 0) std::this_thread::sleep_for(client.settle);
  for (int k = 0; k < client.epochs; ++k) {
    write_all(base_epoch(k));
    std::this_thread::sleep_for(milliseconds(100));
    drain();
  }
  EXPECT_EQ(gpsemu.wait(seconds(20)), 0) << gpsemu.stderr_text();
  drain();
  ::close(fd);
  std::filesystem::remove_all(dir);
  run.log = gpsemu.stderr_text();
  return run;
}

/// An F9P rover (`--receiver ublox-f9p --protocol ubx`): run_rover().
inline RoverRun run_f9p_rover(const std::string& name, const std::string& duration, const RoverClient& client) {
  return run_rover("ublox-f9p", "ubx", name, duration, client);
}

}  // namespace gpsemu::test
