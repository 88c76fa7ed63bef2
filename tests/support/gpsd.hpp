// Test support for the end-to-end tests with the real gpsd: a free TCP port for gpsd to listen on
// (parallel tests and a system gpsd on 2947 do not collide), a connection to it once it listens,
// the JSON watch, its reports split into lines with the TPV fields the tests check, and GpsdWatch:
// gpsd started on a device with one client watching it, as every gpsd test starts it.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "emulator/model/time.hpp"
#include "tests/support/process.hpp"
#include "tests/support/read_deadline.hpp"

namespace gpsemu::test {

inline constexpr const char* kGpsd = "/usr/sbin/gpsd";

/// A TCP port that was free a moment ago (bound to port 0 and released).
inline int free_tcp_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    throw std::runtime_error("cannot find a free port");
  }
  ::close(fd);
  return ntohs(a.sin_port);
}

/// Connects to gpsd on 127.0.0.1:port, retrying (paced by poll timeouts) until it listens; -1 on timeout.
inline int connect_gpsd(int port, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) return fd;
    ::close(fd);
    ::poll(nullptr, 0, 20);  // gpsd is still starting: try again shortly
  }
  return -1;
}

/// Asks gpsd for its JSON reports on a connected socket; false when the write failed.
inline bool watch_json(int sock) {
  const std::string watch = "?WATCH={\"enable\":true,\"json\":true};\n";
  return ::write(sock, watch.data(), watch.size()) == static_cast<ssize_t>(watch.size());
}

/// Milliseconds since UTC midnight of an ISO 8601 time as gpsd writes it.
inline std::int64_t ms_of_day(const std::string& iso) {
  using namespace std::chrono;
  const auto t = parse_iso8601_utc(iso);
  return duration_cast<milliseconds>(t - floor<days>(t)).count();
}

/// The fields of a TPV report the tests check; NaN or empty where gpsd left them out.
struct Tpv {
  int mode = 0;
  std::optional<std::int64_t> time_of_day_ms;  ///< ms since UTC midnight
  double lat_deg = NAN, lon_deg = NAN;
  double eph_m = NAN, epv_m = NAN;  ///< gpsd's horizontal and vertical position error estimates
  double ecef_x_m = NAN, ecef_y_m = NAN, ecef_z_m = NAN;  ///< WGS84 earth-centred position
};

inline Tpv tpv_of(const nlohmann::json& j) {
  const auto number = [&](const char* key) { return j.contains(key) ? j[key].get<double>() : NAN; };
  Tpv r;
  r.mode = j.value("mode", 0);
  if (j.contains("time")) r.time_of_day_ms = ms_of_day(j["time"].get<std::string>());
  r.lat_deg = number("lat");
  r.lon_deg = number("lon");
  r.eph_m = number("eph");
  r.epv_m = number("epv");
  r.ecef_x_m = number("ecefx");
  r.ecef_y_m = number("ecefy");
  r.ecef_z_m = number("ecefz");
  return r;
}

/// gpsd's reports, one JSON object a line, from its socket in any chunking.
class ReportLines {
 public:
  /// Adds `chunk`; calls on_report(json) for each line completed that is an object with a class.
  template <class OnReport>
  void feed(std::string_view chunk, OnReport on_report) {
    buffer_.append(chunk);
    std::size_t nl;
    while ((nl = buffer_.find('\n')) != std::string::npos) {
      const nlohmann::json j = nlohmann::json::parse(buffer_.substr(0, nl), nullptr, false);
      buffer_.erase(0, nl + 1);
      if (!j.is_discarded() && j.is_object() && j.contains("class")) on_report(j);
    }
  }

 private:
  std::string buffer_;
};

/// Whether gpsd may reconfigure the receiver: read-only is `gpsd -b` (it leaves the configuration alone).
enum class GpsdAccess { read_only, read_write };

/// gpsd (`gpsd -N -n [-b] -S <free port> DEVICE`) reading a device, with one client connected (gpsd
/// given 10 s to listen) that asked for its JSON reports. ok() is false, and error() says why, when
/// gpsemu did not start, gpsd is not installed, does not listen or takes no watch. The destructor
/// closes the client and stops gpsd; close_client() and stop() do it earlier, where a test wants it
/// at a given moment.
class GpsdWatch {
 public:
  /// gpsd on `device`.
  GpsdWatch(const std::string& device, GpsdAccess access) { start(device, access); }
  /// gpsd on the pty that `gpsemu` (started with --output pty:LINK) serves, once it logged that it
  /// is on it (at most 20 s).
  GpsdWatch(Process& gpsemu, const std::filesystem::path& link, GpsdAccess access) {
    if (!gpsemu.wait_for_stderr("on /dev/pts", std::chrono::seconds(20))) {
      error_ = "gpsemu did not start: " + gpsemu.stderr_text();
      return;
    }
    start(std::filesystem::read_symlink(link).string(), access);
  }
  ~GpsdWatch() { stop(); }
  GpsdWatch(const GpsdWatch&) = delete;
  GpsdWatch& operator=(const GpsdWatch&) = delete;

  [[nodiscard]] bool ok() const { return error_.empty(); }
  [[nodiscard]] const std::string& error() const { return error_; }
  /// The port gpsd listens on (for other clients: ubxtool, gpspipe).
  [[nodiscard]] int port() const { return port_; }
  /// The watching client's socket (-1 once closed or when gpsd did not listen).
  [[nodiscard]] int socket() const { return sock_; }

  /// Reads the watch for `how_long`, calling on_report(json) for each report, until `until()` says
  /// stop after a read; a report split across calls is completed by the next one.
  template <class OnReport, class Until>
  void read_reports(std::chrono::milliseconds how_long, OnReport on_report, Until until) {
    read_with_deadline(sock_, {how_long}, [&](std::string_view chunk) {
      lines_.feed(chunk, on_report);
      return until();
    });
  }
  template <class OnReport>
  void read_reports(std::chrono::milliseconds how_long, OnReport on_report) {
    read_reports(how_long, on_report, [] { return false; });
  }

  void close_client() {
    if (sock_ >= 0) ::close(sock_);
    sock_ = -1;
  }
  /// Closes the client, then stops gpsd (SIGTERM, up to 10 s).
  void stop() {
    close_client();
    if (!gpsd_) return;
    gpsd_->signal(SIGTERM);
    gpsd_->wait(std::chrono::seconds(10));
    gpsd_.reset();
  }

 private:
  void start(const std::string& device, GpsdAccess access) {
    if (::access(kGpsd, X_OK) != 0) {
      error_ = std::string(kGpsd) + " is missing: tools/setup --with-test-deps installs gpsd (Debian package gpsd)";
      return;
    }
    port_ = free_tcp_port();
    std::vector<std::string> argv{kGpsd, "-N", "-n", "-S", std::to_string(port_), device};
    if (access == GpsdAccess::read_only) argv.insert(argv.begin() + 1, "-b");
    gpsd_.emplace(argv);
    sock_ = connect_gpsd(port_, std::chrono::seconds(10));
    if (sock_ < 0) {
      gpsd_->signal(SIGTERM);
      gpsd_->wait(std::chrono::seconds(5));
      error_ = "gpsd does not listen on port " + std::to_string(port_) + ": " + gpsd_->stderr_text();
      return;
    }
    if (!watch_json(sock_)) error_ = "cannot ask gpsd for reports (?WATCH)";
  }

  std::optional<Process> gpsd_;
  int port_ = 0;
  int sock_ = -1;
  std::string error_;
  ReportLines lines_;
};

}  // namespace gpsemu::test
