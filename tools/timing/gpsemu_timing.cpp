// gpsemu-timing: measures a receiver's output timing the way a client sees it. Reads NMEA from a
// pty or serial device (or a TCP server), stamps the arrival of each epoch's first bytes with
// CLOCK_REALTIME, and compares it with the epoch's ideal time: its UTC time field + latency.
// Reports median offset, p99 and max deviation, and missing/repeated epochs.
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "nmea/parse.hpp"

namespace {

double realtime_s() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<double>(ts.tv_sec) + ts.tv_nsec * 1e-9;
}

int open_device(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) throw std::runtime_error(fmt::format("cannot open {}: {}", path, std::strerror(errno)));
  termios t{};
  if (tcgetattr(fd, &t) == 0) {
    cfmakeraw(&t);
    tcsetattr(fd, TCSANOW, &t);
  }
  return fd;
}

int open_tcp(const std::string& host_port) {
  const auto colon = host_port.rfind(':');
  if (colon == std::string::npos) throw std::runtime_error("--tcp expects HOST:PORT");
  addrinfo hints{}, *res = nullptr;
  hints.ai_socktype = SOCK_STREAM;
  if (getaddrinfo(host_port.substr(0, colon).c_str(), host_port.substr(colon + 1).c_str(), &hints, &res) != 0) {
    throw std::runtime_error("cannot resolve " + host_port);
  }
  const int fd = socket(res->ai_family, SOCK_STREAM, 0);
  const int rc = connect(fd, res->ai_addr, res->ai_addrlen);
  freeaddrinfo(res);
  if (rc != 0) throw std::runtime_error(fmt::format("cannot connect to {}: {}", host_port, std::strerror(errno)));
  return fd;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double idx = p * (v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(idx));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (v[hi] - v[lo]) * (idx - lo);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gpsemu-timing: first-byte arrival of each epoch against UTC epoch time + latency"};
  std::string device, tcp, csv_path;
  double latency_s = 0.05, duration_s = 60.0;
  app.add_option("--device", device, "pty or serial device to read (e.g. /tmp/gpsemu)");
  app.add_option("--tcp", tcp, "HOST:PORT of a tcp output to read instead");
  app.add_option("--latency", latency_s, "the emulator's configured latency, seconds (default 0.05)");
  app.add_option("--duration", duration_s, "how long to measure, seconds (default 60)");
  app.add_option("--csv", csv_path, "write one line per epoch: epoch_time_s,arrival_s,deviation_ms");
  CLI11_PARSE(app, argc, argv);
  if (device.empty() == tcp.empty()) {
    std::fprintf(stderr, "gpsemu-timing: give exactly one of --device or --tcp\n");
    return 2;
  }
  int fd = -1;
  try {
    fd = device.empty() ? open_tcp(tcp) : open_device(device);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gpsemu-timing: %s\n", e.what());
    return 2;
  }

  gpsemu::nmea::StreamReader reader;
  std::vector<double> deviations_ms;
  std::vector<std::pair<double, double>> rows;  // epoch time of day, arrival
  double last_epoch_s = -1.0, period_s = 0.0;
  long missing = 0, repeated = 0;
  bool first = true;  // the first epoch may be cut in half by our start: skip it
  const double end = realtime_s() + duration_s;
  char buf[8192];
  while (realtime_s() < end) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 200) <= 0) continue;
    const double arrival = realtime_s();
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n <= 0) continue;
    for (const auto& s : reader.feed(std::string_view(buf, static_cast<std::size_t>(n)))) {
      std::optional<std::chrono::milliseconds> tod;
      if (s.type == "GGA") {
        if (auto g = gpsemu::nmea::parse_gga(s)) tod = g->time_of_day;
      } else if (s.type == "RMC") {
        if (auto r = gpsemu::nmea::parse_rmc(s)) tod = r->time_of_day;
      }
      if (!tod) continue;
      const double epoch_s = tod->count() / 1000.0;
      if (epoch_s == last_epoch_s) continue;  // another sentence of the same epoch
      if (!first) {
        const double step = std::fmod(epoch_s - last_epoch_s + 86400.0, 86400.0);
        if (period_s == 0.0 || step < period_s - 1e-6) period_s = step;
        if (step == 0.0) ++repeated;
        else if (period_s > 0.0 && step > 1.5 * period_s) missing += std::lround(step / period_s) - 1;
        // The ideal time: the epoch's time of day on the day nearest the arrival.
        const double day0 = std::floor(arrival / 86400.0) * 86400.0;
        double ideal = day0 + epoch_s + latency_s;
        if (ideal - arrival > 43200.0) ideal -= 86400.0;
        if (arrival - ideal > 43200.0) ideal += 86400.0;
        deviations_ms.push_back((arrival - ideal) * 1000.0);
        rows.emplace_back(epoch_s, arrival);
      }
      first = false;
      last_epoch_s = epoch_s;
    }
  }
  ::close(fd);
  if (!csv_path.empty()) {
    std::ofstream csv(csv_path);
    csv << "epoch_time_of_day_s,arrival_unix_s,deviation_ms\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      csv << fmt::format("{:.3f},{:.6f},{:.3f}\n", rows[i].first, rows[i].second, deviations_ms[i]);
    }
  }
  if (deviations_ms.empty()) {
    std::fprintf(stderr, "gpsemu-timing: no epochs received\n");
    return 1;
  }
  std::vector<double> abs_dev;
  for (const double d : deviations_ms) abs_dev.push_back(std::abs(d));
  fmt::print("epochs {} missing {} repeated {} period {:.3f} s\n", deviations_ms.size(), missing, repeated, period_s);
  fmt::print("arrival - (epoch + latency): median {:.3f} ms, p99 {:.3f} ms, max {:.3f} ms, min {:.3f} ms\n",
             percentile(deviations_ms, 0.5), percentile(deviations_ms, 0.99),
             *std::max_element(deviations_ms.begin(), deviations_ms.end()),
             *std::min_element(deviations_ms.begin(), deviations_ms.end()));
  fmt::print("|deviation|: p99 {:.3f} ms, max {:.3f} ms\n", percentile(abs_dev, 0.99),
             *std::max_element(abs_dev.begin(), abs_dev.end()));
  fmt::print("reader stats: sentences {} bad checksum {} malformed {} garbage bytes {}\n",
             reader.stats().sentences_ok, reader.stats().bad_checksum, reader.stats().malformed,
             reader.stats().garbage_bytes);
  return 0;
}
