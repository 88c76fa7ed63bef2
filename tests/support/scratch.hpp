// Test support: scratch directories, whole files, and UDP and TCP sockets to a loopback port: the
// small helpers the end-to-end and integration tests share.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace gpsemu::test {

/// This process's directory under the temporary directory, gpsemu_PID: made on first use and removed
/// with everything in it when the test process exits (set GPSEMU_KEEP_SCRATCH=1 to keep it and look).
inline const std::filesystem::path& scratch_root() {
  struct Root {
    std::filesystem::path path;
    pid_t owner;
    Root()
        : path(std::filesystem::temp_directory_path() / ("gpsemu_" + std::to_string(::getpid()))),
          owner(::getpid()) {
      std::filesystem::remove_all(path);
      std::filesystem::create_directories(path);
    }
    ~Root() {
      // A forked child that exits normally must not take its parent's files with it.
      if (::getpid() != owner || std::getenv("GPSEMU_KEEP_SCRATCH") != nullptr) return;
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const Root root;
  return root.path;
}

/// An empty directory in this process's scratch root: PREFIX_NAME.
inline std::filesystem::path scratch_dir(const std::string& prefix, const std::string& name) {
  const auto dir = scratch_root() / (prefix + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// The whole file (empty when it cannot be read).
inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes `text` to `path` (replacing it) and returns the path.
inline std::filesystem::path write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// Connects `fd` to 127.0.0.1:`port`; returns `fd`, or -1 (and closes it) when that fails.
inline int connect_to_loopback(int fd, std::uint16_t port) {
  if (fd < 0) return -1;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

/// A UDP socket connected to 127.0.0.1:`port`, or -1.
inline int udp_to(std::uint16_t port) {
  return connect_to_loopback(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0), port);
}

/// A TCP socket connected to 127.0.0.1:`port`, or -1; `receive_buffer` > 0 sets SO_RCVBUF first.
inline int tcp_to(std::uint16_t port, int receive_buffer = 0) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd >= 0 && receive_buffer > 0) ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  return connect_to_loopback(fd, port);
}

}  // namespace gpsemu::test
