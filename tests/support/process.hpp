// Test support: start the real gpsemu binary (or another program) with pipes on stdout/stderr,
// keep every stdout chunk with the CLOCK_REALTIME time it was read (to measure when epochs left),
// wait for a stderr line or for exit with poll() and a timeout, and stop it. No sleeps. pump()
// lets a test do its own work (send poses) between reads.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/paths.hpp"

extern char** environ;

namespace gpsemu::test {

inline double realtime_now_s() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

/// A chunk of standard output and when it was read (CLOCK_REALTIME, seconds).
struct Chunk {
  double read_s;
  std::string bytes;
};

class Process {
 public:
  explicit Process(const std::vector<std::string>& argv) {
    int out[2], err[2];
    // Close-on-exec: the child keeps only the copies dup2'ed onto its stdout and stderr.
    if (pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    if (pipe2(err, O_CLOEXEC) != 0) {
      close(out[0]);
      close(out[1]);
      throw std::runtime_error("pipe failed");
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_adddup2(&fa, err[1], 2);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const int rc = posix_spawn(&pid_, args[0], &fa, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    close(out[1]);
    close(err[1]);
    out_ = out[0];
    err_ = err[0];
    if (rc != 0) {
      close(out_);
      close(err_);
      throw std::runtime_error("cannot start " + argv[0]);
    }
    fcntl(out_, F_SETFL, O_NONBLOCK);
    fcntl(err_, F_SETFL, O_NONBLOCK);
  }
  ~Process() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    close(out_);
    close(err_);
  }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  /// Reads what is available, waiting at most `timeout` for something; false once both pipes closed.
  bool pump(std::chrono::milliseconds timeout) {
    if (out_closed_ && err_closed_) return false;
    pollfd p[2] = {{out_closed_ ? -1 : out_, POLLIN, 0}, {err_closed_ ? -1 : err_, POLLIN, 0}};
    if (poll(p, 2, static_cast<int>(timeout.count())) <= 0) return true;
    read_available();
    return !(out_closed_ && err_closed_);
  }

  /// Reads the pipes until `deadline`: for a test that paces its own sending (poses at 50 Hz, a
  /// recorded stream at its pace) while the child writes more than a pipe holds (64 KiB: about a
  /// minute of 1 Hz NMEA, six seconds at 10 Hz with a full sky's GSV), which would block the child.
  void pump_until(std::chrono::steady_clock::time_point deadline) {
    while (true) {
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return;
      if (!pump(left)) {  // both pipes closed: nothing more to read, only the time to let pass
        std::this_thread::sleep_until(deadline);
        return;
      }
    }
  }

  /// Reads until a stderr line containing `needle` arrives after the line the previous call
  /// returned; returns that line (without its newline), or nothing on timeout or exit.
  std::optional<std::string> wait_for_stderr(const std::string& needle, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      std::size_t nl;
      while ((nl = stderr_.find('\n', stderr_seen_)) != std::string::npos) {
        std::string line = stderr_.substr(stderr_seen_, nl - stderr_seen_);
        stderr_seen_ = nl + 1;
        if (line.find(needle) != std::string::npos) return line;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      if (!pump(left) && stderr_.find('\n', stderr_seen_) == std::string::npos) return std::nullopt;
    }
  }

  /// Waits for exit, reading the pipes meanwhile (so the child never blocks on a full pipe); the
  /// exit status (128 + signal when killed), or -1 if it still runs after `timeout`.
  int wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      int status = 0;
      if (pid_ > 0 && waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      if (pid_ < 0) {
        read_available();  // what it wrote before it exited (a daemon it started may hold the pipes)
        return exit_status_;
      }
      if (std::chrono::steady_clock::now() >= deadline) return -1;
      pump(std::chrono::milliseconds(20));
    }
  }

  void signal(int sig) {
    if (pid_ > 0) kill(pid_, sig);
  }
  /// The child's process id while it runs (-1 once waited for).
  [[nodiscard]] pid_t pid() const { return pid_; }

  /// Standard output as read so far, in chunks with their read times.
  [[nodiscard]] const std::vector<Chunk>& chunks() const { return chunks_; }
  [[nodiscard]] const std::string& stdout_text() const { return stdout_; }
  /// Standard error as read so far.
  [[nodiscard]] const std::string& stderr_text() const { return stderr_; }

 private:
  void read_available() {
    char buf[65536];
    while (!out_closed_) {
      const ssize_t n = read(out_, buf, sizeof buf);
      if (n > 0) {
        chunks_.push_back({realtime_now_s(), std::string(buf, static_cast<std::size_t>(n))});
        stdout_.append(buf, static_cast<std::size_t>(n));
        continue;
      }
      if (n == 0) out_closed_ = true;
      break;  // EAGAIN: nothing more for now
    }
    while (!err_closed_) {
      const ssize_t n = read(err_, buf, sizeof buf);
      if (n > 0) {
        stderr_.append(buf, static_cast<std::size_t>(n));
        continue;
      }
      if (n == 0) err_closed_ = true;
      break;
    }
  }

  pid_t pid_ = -1;
  int out_ = -1, err_ = -1;
  bool out_closed_ = false, err_closed_ = false;
  int exit_status_ = -1;
  std::vector<Chunk> chunks_;
  std::string stdout_, stderr_;
  std::size_t stderr_seen_ = 0;  ///< wait_for_stderr() has looked at the lines before this offset
};

/// Runs a program to completion; returns {exit status, stdout, stderr}.
struct Result {
  int status;
  std::string out, err;
};
inline Result run(const std::vector<std::string>& argv, std::chrono::milliseconds timeout = std::chrono::seconds(60)) {
  Process p(argv);
  const int status = p.wait(timeout);
  return {status, p.stdout_text(), p.stderr_text()};
}

/// Runs `argv` followed by `more` to completion (a fixed command line and what one test adds).
inline Result run(std::vector<std::string> argv, const std::vector<std::string>& more,
                  std::chrono::milliseconds timeout = std::chrono::seconds(60)) {
  argv.insert(argv.end(), more.begin(), more.end());
  return run(argv, timeout);
}

/// Reads the child's pipes for `how_long` (while the test watches it run).
inline void pump_for(Process& p, std::chrono::milliseconds how_long) {
  p.pump_until(std::chrono::steady_clock::now() + how_long);
}

/// Waits for `p`'s stderr line holding `needle` that ends in a port (gpsemu's "waiting for poses on
/// 127.0.0.1:PORT") and returns that port; nothing when no such line came within `timeout`.
inline std::optional<std::uint16_t> wait_for_port(Process& p, const std::string& needle,
                                                  std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
  const auto line = p.wait_for_stderr(needle, timeout);
  if (!line) return std::nullopt;
  return static_cast<std::uint16_t>(std::stoi(line->substr(line->rfind(':') + 1)));
}

/// Whether `text` holds `part`.
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Runs `binary --fast --output stdout --log-level warn --start-time 2024-05-01T00:00:00Z ARGS` to
/// completion (batch generation with a fixed start: deterministic NMEA on stdout).
inline Result run_fast(const std::string& binary, const std::vector<std::string>& args) {
  std::vector<std::string> argv{binary, "--fast", "--output", "stdout", "--log-level", "warn",
                                "--start-time", "2024-05-01T00:00:00Z"};
  argv.insert(argv.end(), args.begin(), args.end());
  // A guard against a hang, not a measure (a --fast run waits for nothing): under the sanitizers
  // beside a build, the F9P profile's 5 240 s took over 120 s (about 33 s alone); below CTest's own
  // limit (300 s) so that the test says which run it was.
  return run(argv, std::chrono::seconds(280));
}

}  // namespace gpsemu::test
