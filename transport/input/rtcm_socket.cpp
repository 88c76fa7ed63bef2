// RTCM3 input sockets (see rtcm_socket.hpp).
#include "transport/input/rtcm_socket.hpp"

#include <unistd.h>

#include <netinet/in.h>

#include <algorithm>
#include <chrono>
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

/// A sender's identity: its address and port, as a number (never 0).
std::uint64_t sender_id(const sockaddr_storage& from) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the address's bytes
  const auto mix = [&h](const void* data, std::size_t size) {
    for (std::size_t k = 0; k < size; ++k) h = (h ^ static_cast<const unsigned char*>(data)[k]) * 1099511628211ull;
  };
  if (from.ss_family == AF_INET) {
    const auto* a = reinterpret_cast<const sockaddr_in*>(&from);
    mix(&a->sin_addr, sizeof a->sin_addr);
    mix(&a->sin_port, sizeof a->sin_port);
  } else if (from.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&from);
    mix(&a->sin6_addr, sizeof a->sin6_addr);
    mix(&a->sin6_port, sizeof a->sin6_port);
  }
  return h == 0 ? 1 : h;
}

class UdpRtcmSocket final : public RtcmSocket {
 public:
  explicit UdpRtcmSocket(posix::Endpoint endpoint) : endpoint_(std::move(endpoint)) {
    fd_ = posix::bind_socket({.host = endpoint_.host, .port = endpoint_.port, .type = SOCK_DGRAM,
                              .context = where("udp", endpoint_)});
    endpoint_.port = posix::bound_port(fd_.get());
  }
  std::optional<RtcmBytes> receive() override {
    for (int step = 0; step < 8; ++step) {
      const auto d = posix::receive_datagram(fd_.get(), buffer_);
      if (!d) return std::nullopt;
      const std::uint64_t from = sender_id(d->from);
      if (base_ && from != *base_) {
        if (Clock::now() - base_frame_at_ < std::chrono::seconds(kQuietS)) {
          ++drops_.other_senders;
          continue;
        }
        base_.reset();  // the base went quiet: any sender may be the next one
      }
      return RtcmBytes{std::string_view(buffer_.data(), std::min(d->size, buffer_.size())), from, false};
    }
    return std::nullopt;
  }
  std::string describe() const override { return "udp:" + posix::host_port(endpoint_.host, endpoint_.port); }
  void frame_from(std::uint64_t source) override {
    if (base_ && *base_ != source) return;
    base_ = source;
    base_frame_at_ = Clock::now();
  }
  Drops drops() const override { return drops_; }

 private:
  using Clock = std::chrono::steady_clock;
  posix::Endpoint endpoint_;
  posix::UniqueFd fd_;
  std::array<char, 65536> buffer_{};
  std::optional<std::uint64_t> base_;  ///< the sender whose frames are used
  Clock::time_point base_frame_at_{};
  Drops drops_;
};

class TcpRtcmServer final : public RtcmSocket {
 public:
  explicit TcpRtcmServer(posix::Endpoint endpoint)
      : endpoint_(std::move(endpoint)),
        server_(endpoint_.host, endpoint_.port, where("tcp", endpoint_),
                {.max_clients = kMaxClients, .take_over = [this] { return least_useful(); }}),
        slots_(kMaxClients) {
    endpoint_.port = server_.port();
  }
  std::optional<RtcmBytes> receive() override {
    for (int step = 0; step < 8; ++step) {
      // One read of a connection, then the next ready one: a connection that never stops sending
      // cannot starve the base beside it.
      if (current_) {
        const std::size_t slot = *current_;
        current_.reset();
        if (auto r = read_slot(slot)) return r;
      }
      const auto event = server_.next_event();
      if (!event) return std::nullopt;
      using Kind = posix::TcpServerEvent::Kind;
      if (event->kind == Kind::connected) {
        slots_[event->slot] = {event->serial, {}};
        if (event->replaced) ++drops_.replaced;
        server_.watch(event->slot, true, false);
      } else if (event->kind == Kind::refused) {
        ++drops_.refused;
      } else if (event->kind == Kind::ready && event->readable) {
        current_ = event->slot;
      }
    }
    return std::nullopt;
  }
  std::string describe() const override { return "tcp:" + posix::host_port(endpoint_.host, endpoint_.port); }
  void frame_from(std::uint64_t source) override {
    for (Slot& s : slots_) {
      if (s.serial == source) s.frame_at = Clock::now();
    }
  }
  Drops drops() const override { return drops_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Slot {
    std::uint64_t serial = 0;
    std::optional<Clock::time_point> frame_at;  ///< its last good frame (none: never)
  };

  /// Every slot taken: one that never gave a frame, else the one quiet longest if kQuietS.
  std::optional<std::size_t> least_useful() const {
    std::optional<std::size_t> best;
    // Never a frame before quiet longest; among those that never gave one, the oldest connection
    // (a base that has just connected has its first frame on the way).
    const auto order = [this](std::size_t i) {
      return std::pair(slots_[i].frame_at.value_or(Clock::time_point::min()), slots_[i].serial);
    };
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (!server_.occupied(i)) continue;
      if (!best || order(i) < order(*best)) best = i;
    }
    if (best && slots_[*best].frame_at && Clock::now() - *slots_[*best].frame_at < std::chrono::seconds(kQuietS)) return std::nullopt;
    return best;
  }

  // One read of `slot`: bytes, the end of the connection, or nothing (EAGAIN).
  std::optional<RtcmBytes> read_slot(std::size_t slot) {
    if (!server_.occupied(slot)) return std::nullopt;
    const ssize_t n = ::read(server_.client_fd(slot), buffer_.data(), buffer_.size());
    if (n > 0) return RtcmBytes{std::string_view(buffer_.data(), static_cast<std::size_t>(n)), slots_[slot].serial, false};
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return std::nullopt;
    server_.drop(slot);  // end of file or an error: the stream is over
    return RtcmBytes{{}, slots_[slot].serial, true};
  }

  posix::Endpoint endpoint_;
  posix::TcpServer server_;
  std::vector<Slot> slots_;
  std::optional<std::size_t> current_;
  std::array<char, kReadBytes> buffer_{};
  Drops drops_;
};

}  // namespace

std::unique_ptr<RtcmSocket> open_rtcm_socket(const RtcmInputSpec& spec) {
  if (spec.tcp) return std::make_unique<TcpRtcmServer>(spec.endpoint);
  return std::make_unique<UdpRtcmSocket>(spec.endpoint);
}

}  // namespace gpsemu::transport
