// A host harness around PX4-GPSDrivers' u-blox and NMEA drivers (src/ubx.cpp, src/nmea.cpp of a
// checkout given to tools/driver-check; none of their code is in this project). It plays PX4's GPS
// task (src/drivers/gps/gps.cpp) over a real pty: GPSCallbackPtr reads with poll (at most 50 ms a
// poll, then the wait for 32 characters at the line's baud, as PX4 does), writes, sets the baud
// with termios; configure(), then receive() with PX4's timeout until it fails, then configure
// again after 500 ms, as PX4's loop does. PX4's gps_inject_data topic is this process's standard
// input: bytes read there are written to the receiver before each read, only while the driver's
// shouldInjectRTCM() says so (PX4's handleInjectDataTopic()).
//
// Output: one JSON object a line on stdout (tools/driver-check judges them): "configure" (each
// attempt: its result and duration), "gps" (each sensor_gps the driver publishes), "sat" (each
// satellite_info), "rel" (sensor_gnss_relative), "timeout" (receive() failed), "inject" (bytes
// written to the receiver), "end". Usage:
//   px4-harness --driver ubx|nmea --device PATH --seconds S [--ubx-mode normal|rover-mb-uart1]
//               [--ubx-rate HZ] [--baud B] [--no-sat-info] [--trace FILE]
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "nmea.h"
#include "ubx.h"

namespace {

constexpr unsigned kTimeout5HzMs = 500;   // PX4 gps.cpp TIMEOUT_5HZ: receive() timeout
constexpr unsigned kTimeout1HzMs = 1300;  // TIMEOUT_1HZ: a moving-base rover's
constexpr int kMaxPollMs = 50;            // pollOrRead's longest poll
constexpr std::size_t kCharacterCount = 32;

struct Options {
  std::string driver = "ubx";
  std::string device;
  double seconds = 10;
  std::string ubx_mode = "normal";
  int ubx_rate_hz = 0;
  unsigned baud = 0;  // PX4's SER_GPSx_BAUD: 0 auto-detect
  bool sat_info = true;
  std::string trace;
};

struct Harness {
  int fd = -1;
  unsigned baud = 0;
  GPSHelper* helper = nullptr;
  std::vector<std::uint8_t> inject_pending;
  bool stdin_open = true;
  std::uint64_t injected_bytes = 0;
  std::uint64_t inject_dropped_bytes = 0;
  std::uint64_t rtcm_from_device = 0;
  std::FILE* trace = nullptr;  // --trace: every byte written and read, stamped
  sensor_gnss_relative_s last_rel{};
  bool have_rel = false;
};

double now_wall_s();

// One trace line: direction ('>' to the receiver, '<' from it, 'I' injected), wall time, hex bytes.
void trace(Harness& h, char dir, const void* data, std::size_t n) {
  if (h.trace == nullptr || n == 0) return;
  std::fprintf(h.trace, "%c %.6f ", dir, now_wall_s());
  for (std::size_t i = 0; i < n; ++i) std::fprintf(h.trace, "%02x", static_cast<const std::uint8_t*>(data)[i]);
  std::fputc('\n', h.trace);
}

double now_wall_s() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

speed_t speed_for(unsigned baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    default: return B0;
  }
}

int set_baud(Harness& h, unsigned baud) {
  const speed_t speed = speed_for(baud);
  if (speed == B0) {
    std::fprintf(stderr, "harness: unknown baud %u\n", baud);
    return -EINVAL;
  }
  termios tio{};
  if (tcgetattr(h.fd, &tio) != 0) return -errno;
  cfmakeraw(&tio);
  cfsetispeed(&tio, speed);
  cfsetospeed(&tio, speed);
  if (tcsetattr(h.fd, TCSANOW, &tio) != 0) return -errno;
  h.baud = baud;
  return 0;
}

// PX4's handleInjectDataTopic(): what the "topic" (stdin) holds goes to the receiver when the driver
// allows injection, otherwise it is dropped (PX4 leaves it in the topic, overwritten by newer data).
void handle_inject(Harness& h) {
  if (h.stdin_open) {
    for (;;) {
      pollfd p{STDIN_FILENO, POLLIN, 0};
      if (poll(&p, 1, 0) <= 0 || (p.revents & (POLLIN | POLLHUP)) == 0) break;
      std::uint8_t buf[4096];
      const ssize_t n = read(STDIN_FILENO, buf, sizeof buf);
      if (n <= 0) {
        h.stdin_open = false;
        break;
      }
      h.inject_pending.insert(h.inject_pending.end(), buf, buf + n);
    }
  }
  if (h.inject_pending.empty()) return;
  if (h.helper == nullptr || !h.helper->shouldInjectRTCM()) {
    h.inject_dropped_bytes += h.inject_pending.size();
    h.inject_pending.clear();
    return;
  }
  const ssize_t n = write(h.fd, h.inject_pending.data(), h.inject_pending.size());
  if (n > 0) {
    trace(h, 'I', h.inject_pending.data(), static_cast<std::size_t>(n));
    h.injected_bytes += static_cast<std::uint64_t>(n);
    h.inject_pending.erase(h.inject_pending.begin(), h.inject_pending.begin() + n);
  }
}

int poll_or_read(Harness& h, std::uint8_t* buf, int len, int timeout_ms) {
  handle_inject(h);
  pollfd p{h.fd, POLLIN, 0};
  int ret = poll(&p, 1, std::min(kMaxPollMs, timeout_ms));
  if (ret > 0) {
    if ((p.revents & POLLIN) == 0) return -1;
    const unsigned baud = h.baud == 0 ? 115200 : h.baud;
    usleep(static_cast<useconds_t>(kCharacterCount * 1000000u / (baud / 10)));
    ret = static_cast<int>(read(h.fd, buf, static_cast<std::size_t>(len)));
    if (ret > 0) trace(h, '<', buf, static_cast<std::size_t>(ret));
  }
  return ret;
}

int callback(GPSCallbackType type, void* data1, int data2, void* user) {
  auto& h = *static_cast<Harness*>(user);
  switch (type) {
    case GPSCallbackType::readDeviceData: {
      int timeout = 0;
      std::memcpy(&timeout, data1, sizeof timeout);
      return poll_or_read(h, static_cast<std::uint8_t*>(data1), data2, timeout);
    }
    case GPSCallbackType::writeDeviceData:
      trace(h, '>', data1, static_cast<std::size_t>(data2));
      return static_cast<int>(write(h.fd, data1, static_cast<std::size_t>(data2)));
    case GPSCallbackType::setBaudrate:
      return set_baud(h, static_cast<unsigned>(data2));
    case GPSCallbackType::gotRTCMMessage:
      ++h.rtcm_from_device;
      return 0;
    case GPSCallbackType::gotRelativePositionMessage:
      if (data1 != nullptr && data2 == static_cast<int>(sizeof(sensor_gnss_relative_s))) {
        h.last_rel = *static_cast<sensor_gnss_relative_s*>(data1);
        h.have_rel = true;
      }
      return 0;
    case GPSCallbackType::surveyInStatus:
    case GPSCallbackType::setClock:
      return 0;
  }
  return 0;
}

void print_gps(const sensor_gps_s& g) {
  std::printf(
      "{\"ev\":\"gps\",\"wall\":%.6f,\"time_utc_usec\":%" PRIu64
      ",\"lat\":%.10f,\"lon\":%.10f,\"alt_msl\":%.4f,\"alt_ellipsoid\":%.4f,\"eph\":%.4f,\"epv\":%.4f,"
      "\"hdop\":%.2f,\"vdop\":%.2f,\"vel\":%.4f,\"vel_n\":%.4f,\"vel_e\":%.4f,\"vel_d\":%.4f,\"cog\":%.5f,"
      "\"vel_ned_valid\":%d,\"s_var\":%.4f,\"fix\":%u,\"sats\":%u,\"noise\":%d,\"agc\":%u,\"jam_ind\":%d,"
      "\"jam_state\":%u,\"spoof\":%u,\"heading\":%s,\"heading_acc\":%s,\"rtcm_used\":%u,\"rtcm_crc_failed\":%d}\n",
      now_wall_s(), g.time_utc_usec, g.latitude_deg, g.longitude_deg, g.altitude_msl_m, g.altitude_ellipsoid_m,
      static_cast<double>(g.eph), static_cast<double>(g.epv), static_cast<double>(g.hdop),
      static_cast<double>(g.vdop), static_cast<double>(g.vel_m_s), static_cast<double>(g.vel_n_m_s),
      static_cast<double>(g.vel_e_m_s), static_cast<double>(g.vel_d_m_s), static_cast<double>(g.cog_rad),
      g.vel_ned_valid ? 1 : 0, static_cast<double>(g.s_variance_m_s), g.fix_type, g.satellites_used,
      g.noise_per_ms, g.automatic_gain_control, g.jamming_indicator, g.jamming_state, g.spoofing_state,
      std::isfinite(g.heading) ? std::to_string(g.heading).c_str() : "null",
      std::isfinite(g.heading_accuracy) ? std::to_string(g.heading_accuracy).c_str() : "null", g.rtcm_msg_used,
      g.rtcm_crc_failed ? 1 : 0);
}

void print_sat(const satellite_info_s& s) {
  unsigned used = 0;
  for (unsigned i = 0; i < s.count && i < satellite_info_s::SAT_INFO_MAX_SATELLITES; ++i) used += s.used[i] != 0;
  std::printf("{\"ev\":\"sat\",\"wall\":%.6f,\"count\":%u,\"used\":%u}\n", now_wall_s(), s.count, used);
}

void print_rel(const sensor_gnss_relative_s& r) {
  std::printf(
      "{\"ev\":\"rel\",\"wall\":%.6f,\"n\":%.4f,\"e\":%.4f,\"d\":%.4f,\"length\":%.4f,\"heading\":%s,"
      "\"heading_valid\":%d,\"rel_valid\":%d,\"fixed\":%d,\"moving_base\":%d}\n",
      now_wall_s(), static_cast<double>(r.position[0]), static_cast<double>(r.position[1]),
      static_cast<double>(r.position[2]), static_cast<double>(r.position_length),
      std::isfinite(r.heading) ? std::to_string(r.heading).c_str() : "null", r.heading_valid ? 1 : 0,
      r.relative_position_valid ? 1 : 0, r.carrier_solution_fixed ? 1 : 0, r.moving_base_mode ? 1 : 0);
}

bool parse_args(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "harness: %s needs a value\n", name);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--driver") o.driver = value("--driver");
    else if (a == "--device") o.device = value("--device");
    else if (a == "--seconds") o.seconds = std::atof(value("--seconds"));
    else if (a == "--ubx-mode") o.ubx_mode = value("--ubx-mode");
    else if (a == "--ubx-rate") o.ubx_rate_hz = std::atoi(value("--ubx-rate"));
    else if (a == "--no-sat-info") o.sat_info = false;
    else if (a == "--baud") o.baud = static_cast<unsigned>(std::atoi(value("--baud")));
    else if (a == "--trace") o.trace = value("--trace");
    else {
      std::fprintf(stderr, "harness: unknown argument %s\n", argv[i]);
      return false;
    }
  }
  if (o.device.empty() || (o.driver != "ubx" && o.driver != "nmea") ||
      (o.ubx_mode != "normal" && o.ubx_mode != "rover-mb-uart1") || o.seconds <= 0) {
    std::fprintf(stderr, "harness: --driver ubx|nmea --device PATH --seconds S [--ubx-mode normal|rover-mb-uart1]\n");
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  if (!parse_args(argc, argv, opt)) return 2;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  Harness h;
  h.fd = open(opt.device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (h.fd < 0) {
    std::fprintf(stderr, "harness: cannot open %s: %s\n", opt.device.c_str(), std::strerror(errno));
    return 2;
  }
  if (!opt.trace.empty()) h.trace = std::fopen(opt.trace.c_str(), "w");
  const int flags = fcntl(h.fd, F_GETFL);
  fcntl(h.fd, F_SETFL, flags & ~O_NONBLOCK);
  set_baud(h, 38400);

  const bool rover = opt.ubx_mode == "rover-mb-uart1";
  const GPSDriverUBX::Settings settings{
      .dynamic_model = 7,  // PX4 defaults: GPS_UBX_DYNMODEL 7, GPS_UBX_BAUD2 57600, the rest 0/off
      .dgnss_timeout = 0,
      .min_cno = 0,
      .min_elev = 0,
      .output_rate = static_cast<std::uint8_t>(opt.ubx_rate_hz),
      .heading_offset = 0.f,
      .uart2_baudrate = 57600,
      .ppk_output = false,
      .jam_det_sensitivity_hi = false,
      .mode = rover ? GPSDriverUBX::UBXMode::RoverWithMovingBaseUART1 : GPSDriverUBX::UBXMode::Normal,
  };
  sensor_gps_s report{};
  satellite_info_s sat{};
  const gps_abstime end = gps_absolute_time() + static_cast<gps_abstime>(opt.seconds * 1e6);
  unsigned attempts = 0;
  while (gps_absolute_time() < end) {
    std::unique_ptr<GPSHelper> helper;
    if (opt.driver == "ubx") {
      helper = std::make_unique<GPSDriverUBX>(GPSHelper::Interface::UART, &callback, &h, &report,
                                              opt.sat_info ? &sat : nullptr, settings);
    } else {
      helper = std::make_unique<GPSDriverNMEA>(&callback, &h, &report, opt.sat_info ? &sat : nullptr, 0.f);
    }
    h.helper = helper.get();
    GPSHelper::GPSConfig config{};
    config.output_mode = GPSHelper::OutputMode::GPS;
    config.gnss_systems = GPSHelper::GNSSSystemsMask::RECEIVER_DEFAULTS;
    config.interface_protocols = GPSHelper::InterfaceProtocolsMask::ALL_DISABLED;
    config.cfg_wipe = false;
    unsigned baud = opt.baud;
    const gps_abstime t0 = gps_absolute_time();
    const int cret = helper->configure(baud, config);
    ++attempts;
    int board = opt.driver == "ubx" ? static_cast<int>(static_cast<GPSDriverUBX*>(helper.get())->board()) : -1;
    std::printf("{\"ev\":\"configure\",\"wall\":%.6f,\"attempt\":%u,\"ret\":%d,\"ms\":%.1f,\"baud\":%u,\"board\":%d}\n",
                now_wall_s(), attempts, cret, static_cast<double>(gps_absolute_time() - t0) / 1000.0, baud, board);
    if (cret == 0) {
      report = sensor_gps_s{};
      report.heading = NAN;
      const unsigned timeout = rover ? kTimeout1HzMs : kTimeout5HzMs;
      int ret = 0;
      while (gps_absolute_time() < end && (ret = helper->receive(timeout)) > 0) {
        if (ret & 1) print_gps(report);
        if (opt.sat_info && (ret & 2)) print_sat(sat);
        if (h.have_rel) {
          print_rel(h.last_rel);
          h.have_rel = false;
        }
      }
      if (ret <= 0 && gps_absolute_time() < end) {
        std::printf("{\"ev\":\"timeout\",\"wall\":%.6f,\"ret\":%d}\n", now_wall_s(), ret);
      }
    }
    h.helper = nullptr;
    if (gps_absolute_time() < end) gps_usleep(500000);  // PX4 waits 500 ms before it starts over
  }
  std::printf("{\"ev\":\"end\",\"wall\":%.6f,\"attempts\":%u,\"injected\":%" PRIu64 ",\"inject_dropped\":%" PRIu64
              ",\"rtcm_from_device\":%" PRIu64 "}\n",
              now_wall_s(), attempts, h.injected_bytes, h.inject_dropped_bytes, h.rtcm_from_device);
  close(h.fd);
  if (h.trace != nullptr) std::fclose(h.trace);
  return 0;
}
