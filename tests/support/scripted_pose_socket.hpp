// A scripted pose socket (transport::PoseSocket returning queued events: kind, bytes, arrival,
// sender) and a recording spdlog sink, for the pose sources' unit tests (socket_source_test,
// mavlink_source_test): the source sees the events a real socket would return, the test reads
// what it logged.
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include "emulator/model/time.hpp"
#include "transport/input/pose_socket.hpp"

namespace gpsemu::test {

struct Scripted {
  transport::ReceivedMessage::Kind kind;
  std::string bytes;
  UtcNs arrival;
  std::uint64_t sender;
  std::string name;
  std::uint64_t count = 1;  ///< kernel_dropped: how many datagrams
};

class FakeSocket final : public transport::PoseSocket {
 public:
  explicit FakeSocket(std::deque<Scripted>* queue) : queue_(queue) {}
  std::optional<transport::ReceivedMessage> receive() override {
    if (queue_->empty()) return std::nullopt;
    current_ = queue_->front();
    queue_->pop_front();
    transport::ReceivedMessage m;
    m.kind = current_.kind;
    m.bytes = current_.bytes;
    m.arrival = current_.arrival;
    m.sender = current_.sender;
    m.sender_name = current_.name;
    m.count = current_.count;
    return m;
  }
  int poll_fd() const override { return -1; }
  std::string describe() const override { return "fake:1"; }
  std::uint16_t port() const override { return 1; }

 private:
  std::deque<Scripted>* queue_;
  Scripted current_;
};

class RecordingSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  std::string text;

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    text.append(msg.payload.data(), msg.payload.size());
    text += '\n';
  }
  void flush_() override {}
};

}  // namespace gpsemu::test
