// Test support: a socat pseudo-terminal pair standing in for a UART and the cable to the vehicle
// computer: the emulator opens link A, the test reads link B. Started from the test, ready when
// socat says so on its stderr (poll with a timeout, no sleeps), stopped (SIGTERM: socat removes
// its links) at the end.
#pragma once

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "tests/support/process.hpp"

namespace gpsemu::test {

/// The socat binary, or empty when it is not installed (tools/setup --with-test-deps installs it).
inline std::string socat_path() {
  for (const char* p : {"/usr/bin/socat", "/bin/socat", "/usr/local/bin/socat"}) {
    if (::access(p, X_OK) == 0) return p;
  }
  return {};
}

class SocatPair {
 public:
  /// Starts `socat -d -d pty,raw,echo=0,link=A pty,raw,echo=0,link=B` and waits until both links
  /// exist and socat transfers data. Throws std::runtime_error with socat's output otherwise.
  SocatPair(std::filesystem::path a, std::filesystem::path b) : a_(std::move(a)), b_(std::move(b)) {
    const std::string socat = socat_path();
    if (socat.empty()) throw std::runtime_error("socat is not installed (run tools/setup --with-test-deps)");
    process_ = std::make_unique<Process>(std::vector<std::string>{
        socat, "-d", "-d", "pty,raw,echo=0,link=" + a_.string(), "pty,raw,echo=0,link=" + b_.string()});
    if (!process_->wait_for_stderr("starting data transfer loop", std::chrono::seconds(10))) {
      throw std::runtime_error("socat did not start: " + process_->stderr_text());
    }
  }
  ~SocatPair() { stop(); }
  SocatPair(const SocatPair&) = delete;
  SocatPair& operator=(const SocatPair&) = delete;

  /// Stops socat as an unplugged cable would go: the pty's other side closes (the emulator sees a
  /// hang-up) and socat removes its links.
  void stop() {
    if (!process_) return;
    process_->signal(SIGTERM);
    (void)process_->wait(std::chrono::seconds(5));
    process_.reset();
  }

  [[nodiscard]] const std::filesystem::path& a() const { return a_; }
  [[nodiscard]] const std::filesystem::path& b() const { return b_; }

 private:
  std::filesystem::path a_, b_;
  std::unique_ptr<Process> process_;
};

/// Opens a link of the pair the way a vehicle computer opens its GPS port: raw, non-blocking.
inline int open_raw(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open " + path.string());
  termios tio{};
  ::tcgetattr(fd, &tio);
  ::cfmakeraw(&tio);
  ::tcsetattr(fd, TCSANOW, &tio);
  return fd;
}

}  // namespace gpsemu::test
