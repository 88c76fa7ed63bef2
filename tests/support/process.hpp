// Test support: start the real gpsemu binary (or another program) with pipes on stdout/stderr,
// wait for a line with poll() and a timeout, and stop it. No sleeps.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

extern char** environ;

namespace gpsemu::test {

class Process {
 public:
  explicit Process(const std::vector<std::string>& argv) {
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
    if (posix_spawn(&pid_, args[0], &fa, nullptr, args.data(), environ) != 0) {
      throw std::runtime_error("cannot start " + argv[0]);
    }
    posix_spawn_file_actions_destroy(&fa);
    close(out[1]);
    close(err[1]);
    out_ = out[0];
    err_ = err[0];
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

  /// Reads stderr until a line containing `needle` arrives; returns that line, or nothing on timeout.
  std::optional<std::string> wait_for_stderr(const std::string& needle, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      std::size_t nl;
      while ((nl = err_buf_.find('\n')) != std::string::npos) {
        std::string line = err_buf_.substr(0, nl);
        stderr_text_ += line + "\n";
        err_buf_.erase(0, nl + 1);
        if (line.find(needle) != std::string::npos) return line;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      pollfd p{err_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
      char buf[4096];
      const ssize_t n = read(err_, buf, sizeof buf);
      if (n <= 0) return std::nullopt;
      err_buf_.append(buf, static_cast<std::size_t>(n));
    }
  }

  void signal(int sig) { kill(pid_, sig); }
  /// The child's process id while it runs (-1 once waited for).
  [[nodiscard]] pid_t pid() const { return pid_; }

  /// Waits for exit (polling the pipes so the child never blocks on a full pipe); returns the
  /// exit status, or -1 on timeout. Collects the rest of stdout and stderr.
  int wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      drain();
      int status = 0;
      const pid_t r = waitpid(pid_, &status, WNOHANG);
      if (r == pid_) {
        pid_ = -1;
        drain();
        stderr_text_ += err_buf_;
        err_buf_.clear();
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      pollfd p[2] = {{out_, POLLIN, 0}, {err_, POLLIN, 0}};
      poll(p, 2, 20);
    }
    return -1;
  }

  const std::string& stdout_text() const { return stdout_text_; }
  const std::string& stderr_text() const { return stderr_text_; }

 private:
  void drain() {
    char buf[65536];
    ssize_t n;
    while ((n = read(out_, buf, sizeof buf)) > 0) stdout_text_.append(buf, static_cast<std::size_t>(n));
    while ((n = read(err_, buf, sizeof buf)) > 0) err_buf_.append(buf, static_cast<std::size_t>(n));
  }
  pid_t pid_ = -1;
  int out_ = -1, err_ = -1;
  std::string err_buf_, stdout_text_, stderr_text_;
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

}  // namespace gpsemu::test
