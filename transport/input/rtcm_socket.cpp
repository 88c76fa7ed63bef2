// RTCM3 input sockets (see rtcm_socket.hpp).
#include "transport/input/rtcm_socket.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <utility>
#include <cerrno>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "transport/posix/tcp_server.hpp"

namespace gpsemu::transport {
namespace {

constexpr std::size_t kReadBytes = 4096;  // one read a call: the caller bounds its work
constexpr std::size_t kMaxClients = 4;

std::string where(std::string_view kind, const posix::Endpoint& e) {
  return fmt::format("--rtcm: cannot listen on {}:{}", kind, posix::host_port(e.host, e.port));
}

class UdpRtcmSocket final : public RtcmSocket {
 public:
  explicit UdpRtcmSocket(posix::Endpoint endpoint) : endpoint_(std::move(endpoint)) {
    fd_ = posix::bind_socket({.host = endpoint_.host, .port = endpoint_.port, .type = SOCK_DGRAM,
                              .context = where("udp", endpoint_)});
    endpoint_.port = posix::bound_port(fd_.get());
  }
  std::optional<RtcmBytes> receive() override {
    const auto d = posix::receive_datagram(fd_.get(), buffer_);
    if (!d) return std::nullopt;
    return RtcmBytes{std::string_view(buffer_.data(), std::min(d->size, buffer_.size())), 0, false};
  }
  std::string describe() const override { return "udp:" + posix::host_port(endpoint_.host, endpoint_.port); }

 private:
  posix::Endpoint endpoint_;
  posix::UniqueFd fd_;
  std::array<char, 65536> buffer_{};
};

class TcpRtcmServer final : public RtcmSocket {
 public:
  explicit TcpRtcmServer(posix::Endpoint endpoint)
      : endpoint_(std::move(endpoint)),
        server_(endpoint_.host, endpoint_.port, where("tcp", endpoint_), {.max_clients = kMaxClients}),
        serials_(kMaxClients, 0) {
    endpoint_.port = server_.port();
  }
  std::optional<RtcmBytes> receive() override {
    for (int step = 0; step < 8; ++step) {
      if (current_) {
        if (auto r = read_slot(*current_)) return r;
        current_.reset();
      }
      const auto event = server_.next_event();
      if (!event) return std::nullopt;
      using Kind = posix::TcpServerEvent::Kind;
      if (event->kind == Kind::connected) {
        serials_[event->slot] = event->serial;
        server_.watch(event->slot, true, false);
      } else if (event->kind == Kind::ready && event->readable) {
        current_ = event->slot;
      }
    }
    return std::nullopt;
  }
  std::string describe() const override { return "tcp:" + posix::host_port(endpoint_.host, endpoint_.port); }

 private:
  // One read of `slot`: bytes, the end of the connection, or nothing (EAGAIN).
  std::optional<RtcmBytes> read_slot(std::size_t slot) {
    if (!server_.occupied(slot)) return std::nullopt;
    const ssize_t n = ::read(server_.client_fd(slot), buffer_.data(), buffer_.size());
    if (n > 0) return RtcmBytes{std::string_view(buffer_.data(), static_cast<std::size_t>(n)), serials_[slot], false};
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return std::nullopt;
    server_.drop(slot);  // end of file or an error: the stream is over
    return RtcmBytes{{}, serials_[slot], true};
  }

  posix::Endpoint endpoint_;
  posix::TcpServer server_;
  std::vector<std::uint64_t> serials_;
  std::optional<std::size_t> current_;
  std::array<char, kReadBytes> buffer_{};
};

}  // namespace

RtcmInputSpec parse_rtcm_input_spec(std::string_view text) {
  RtcmInputSpec spec;
  if (text.starts_with("tcp:")) {
    spec.tcp = true;
  } else if (text.starts_with("udp:")) {
    spec.tcp = false;
  } else {
    throw std::invalid_argument(fmt::format("expected tcp:[HOST:]PORT or udp:[HOST:]PORT, got '{}'", text));
  }
  spec.endpoint = posix::parse_endpoint(text.substr(4));
  return spec;
}

std::unique_ptr<RtcmSocket> open_rtcm_socket(const RtcmInputSpec& spec) {
  if (spec.tcp) return std::make_unique<TcpRtcmServer>(spec.endpoint);
  return std::make_unique<UdpRtcmSocket>(spec.endpoint);
}

}  // namespace gpsemu::transport
