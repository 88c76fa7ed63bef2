// The TCP client side of the pose input (pose_socket.hpp: open_tcp_pose_client): gpsemu connects
// to a simulator's stream port (ArduPilot SITL's MAVLink on 5760) instead of listening. One
// non-blocking socket; the connection is attempted, checked and retried from receive(), which the
// source calls every epoch, so a simulator started after gpsemu, or restarted, is picked up.
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "transport/input/pose_socket.hpp"
#include "transport/posix/errors.hpp"
#include "transport/posix/sockets.hpp"
#include "transport/posix/wall_clock.hpp"

namespace gpsemu::transport {
namespace {

constexpr std::uint64_t kTcpBit = 1ull << 63;
/// A connection attempt not answered within this is abandoned and retried.
constexpr std::chrono::seconds kConnectTimeout{5};

class TcpPoseClient final : public PoseSocket {
 public:
  TcpPoseClient(const PoseEndpoint& endpoint, const PoseSocketOptions& options, std::chrono::nanoseconds retry)
      : endpoint_(endpoint), target_(posix::host_port(endpoint.host, endpoint.port)),
        buffer_(options.max_message_bytes), retry_(retry) {
    if (endpoint.port == 0) throw std::runtime_error(fmt::format("cannot connect to tcp:{}: port 0", target_));
    addrinfo hints{};
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (const int rc = ::getaddrinfo(endpoint.host.c_str(), nullptr, &hints, &found); rc != 0) {
      throw std::runtime_error(fmt::format("cannot connect to tcp:{}: host '{}': {}", target_, endpoint.host,
                                           gai_strerror(rc)));
    }
    ::freeaddrinfo(found);
    start_connect(posix::wall_clock_now());
  }

  bool reply(std::uint64_t /*sender*/, std::span<const std::uint8_t> bytes) override {
    if (state_ != State::connected) return false;
    const ssize_t n = ::send(fd_.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    return n == static_cast<ssize_t>(bytes.size());
  }

  std::optional<ReceivedMessage> receive() override {
    const posix::WallTime now = posix::wall_clock_now();
    switch (state_) {
      case State::waiting:
        if (now >= next_attempt_) start_connect(now);
        return std::nullopt;
      case State::connecting: return check_connect(now);
      case State::connected: break;
    }
    const ssize_t n = ::read(fd_.get(), buffer_.data(), buffer_.size());
    if (n > 0) {
      ReceivedMessage m = event(ReceivedMessage::Kind::message, now);
      m.bytes = std::string_view(buffer_.data(), static_cast<std::size_t>(n));
      return m;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return std::nullopt;
    ReceivedMessage m = event(ReceivedMessage::Kind::disconnected, now);
    spdlog::warn("tcp:{}: {}; reconnecting every {} ms", target_,
                 n == 0 ? std::string("closed by the peer") : posix::errno_text(errno),
                 std::chrono::duration_cast<std::chrono::milliseconds>(retry_).count());
    wait_to_retry(now);
    return m;
  }

  int poll_fd() const override { return state_ == State::waiting ? -1 : fd_.get(); }
  std::string describe() const override { return "tcp:" + target_; }
  std::uint16_t port() const override { return endpoint_.port; }

 private:
  enum class State { waiting, connecting, connected };

  ReceivedMessage event(ReceivedMessage::Kind kind, posix::WallTime now) const {
    ReceivedMessage m;
    m.kind = kind;
    m.arrival = now;
    m.sender = serial_ | kTcpBit;
    m.sender_name = name_;
    return m;
  }

  void start_connect(posix::WallTime now) {
    ++serial_;
    name_ = fmt::format("{} (tcp #{})", target_, serial_);
    attempt_started_ = now;
    try {
      fd_ = posix::open_socket({.host = endpoint_.host, .port = endpoint_.port, .type = SOCK_STREAM, .passive = false,
                                .context = "cannot connect to tcp:" + target_},
                               [](int fd, const addrinfo& ai) {
                                 const int rc = ::connect(fd, ai.ai_addr, ai.ai_addrlen);
                                 return rc == 0 || errno == EINPROGRESS ? 0 : errno;
                               });
      state_ = State::connecting;
    } catch (const std::runtime_error& e) {
      failed(now, e.what());
    }
  }

  std::optional<ReceivedMessage> check_connect(posix::WallTime now) {
    pollfd p{fd_.get(), POLLOUT, 0};
    if (::poll(&p, 1, 0) <= 0) {
      if (now - attempt_started_ > kConnectTimeout) failed(now, fmt::format("cannot connect to tcp:{}: no answer", target_));
      return std::nullopt;
    }
    int err = 0;
    socklen_t len = sizeof err;
    if (::getsockopt(fd_.get(), SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
    if (err != 0) {
      failed(now, fmt::format("cannot connect to tcp:{}: {}", target_, posix::errno_text(err)));
      return std::nullopt;
    }
    state_ = State::connected;
    spdlog::info("connected to tcp:{}{}", target_, failures_ > 0 ? fmt::format(" after {} failed attempts", failures_) : "");
    failures_ = 0;
    return event(ReceivedMessage::Kind::connected, now);
  }

  /// Closes the socket and waits `retry_`; the first failure of a streak is logged (`why` names the target).
  void failed(posix::WallTime now, const std::string& why) {
    if (failures_++ == 0) {
      spdlog::warn("{}; retrying every {} ms", why,
                   std::chrono::duration_cast<std::chrono::milliseconds>(retry_).count());
    }
    wait_to_retry(now);
  }

  void wait_to_retry(posix::WallTime now) {
    fd_ = posix::UniqueFd();
    state_ = State::waiting;
    next_attempt_ = now + retry_;
  }

  PoseEndpoint endpoint_;
  std::string target_;
  std::vector<char> buffer_;
  std::chrono::nanoseconds retry_;
  posix::UniqueFd fd_;
  State state_ = State::waiting;
  posix::WallTime next_attempt_{};
  posix::WallTime attempt_started_{};
  std::uint64_t serial_ = 0;
  std::uint64_t failures_ = 0;
  std::string name_;
};

}  // namespace

std::unique_ptr<PoseSocket> open_tcp_pose_client(const PoseEndpoint& endpoint, const PoseSocketOptions& options,
                                                 std::chrono::nanoseconds retry) {
  return std::make_unique<TcpPoseClient>(endpoint, options, retry);
}

}  // namespace gpsemu::transport
