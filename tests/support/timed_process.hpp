// Test support: start the gpsemu binary with pipes on stdout/stderr and keep every stdout chunk
// with the CLOCK_REALTIME time it was read, to measure when epochs left. Waits with poll() and
// timeouts; no sleeps. pump() lets a test do its own work (send poses) between reads.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

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

class TimedProcess {
 public:
  explicit TimedProcess(const std::vector<std::string>& argv) {
    int out[2], err[2];
    if (pipe(out) != 0 || pipe(err) != 0) throw std::runtime_error("pipe failed");
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_adddup2(&fa, err[1], 2);
    posix_spawn_file_actions_addclose(&fa, out[0]);
    posix_spawn_file_actions_addclose(&fa, err[0]);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const int rc = posix_spawn(&pid_, args[0], &fa, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    close(out[1]);
    close(err[1]);
    out_ = out[0];
    err_ = err[0];
    if (rc != 0) throw std::runtime_error("cannot start " + argv[0]);
    fcntl(out_, F_SETFL, O_NONBLOCK);
    fcntl(err_, F_SETFL, O_NONBLOCK);
  }
  ~TimedProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    close(out_);
    close(err_);
  }
  TimedProcess(const TimedProcess&) = delete;
  TimedProcess& operator=(const TimedProcess&) = delete;

  /// Reads what is available, waiting at most `timeout` for something; false once both pipes closed.
  bool pump(std::chrono::milliseconds timeout) {
    if (out_closed_ && err_closed_) return false;
    pollfd p[2] = {{out_closed_ ? -1 : out_, POLLIN, 0}, {err_closed_ ? -1 : err_, POLLIN, 0}};
    if (poll(p, 2, static_cast<int>(timeout.count())) <= 0) return true;
    read_available();
    return !(out_closed_ && err_closed_);
  }

  /// Reads until a stderr line containing `needle` arrives; returns that line, or nothing on timeout.
  std::optional<std::string> wait_for_stderr(const std::string& needle, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::size_t from = 0;
    while (true) {
      const auto at = stderr_.find(needle, from);
      if (at != std::string::npos) {
        const auto nl = stderr_.find('\n', at);
        if (nl != std::string::npos) {
          const auto start = stderr_.rfind('\n', at);
          return stderr_.substr(start == std::string::npos ? 0 : start + 1, nl - (start == std::string::npos ? 0 : start + 1));
        }
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      if (!pump(left) && stderr_.find(needle, from) == std::string::npos) return std::nullopt;
    }
  }

  /// Waits for exit, reading the pipes meanwhile; the exit status, or -1 on timeout.
  int wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      pump(std::chrono::milliseconds(20));
      int status = 0;
      if (pid_ > 0 && waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      if (pid_ < 0) {
        while (pump(std::chrono::milliseconds(0)) && !(out_closed_ && err_closed_)) {
        }
        return exit_status_;
      }
    }
    return -1;
  }

  void signal(int sig) {
    if (pid_ > 0) kill(pid_, sig);
  }

  [[nodiscard]] const std::vector<Chunk>& chunks() const { return chunks_; }
  [[nodiscard]] std::string stdout_text() const {
    std::string all;
    for (const auto& c : chunks_) all += c.bytes;
    return all;
  }
  [[nodiscard]] const std::string& stderr_text() const { return stderr_; }

 private:
  void read_available() {
    char buf[65536];
    while (!out_closed_) {
      const ssize_t n = read(out_, buf, sizeof buf);
      if (n > 0) {
        chunks_.push_back({realtime_now_s(), std::string(buf, static_cast<std::size_t>(n))});
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
  std::string stderr_;
};

}  // namespace gpsemu::test
