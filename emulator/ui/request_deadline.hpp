// The bench view's guard against slow requests (slowloris): cpp-httplib times out each read, not
// a whole request, so a client sending one header byte a second would hold a worker for ever and
// 70 of them every worker. This watch looks at the server's connections every quarter second
// (transport/posix/sockets.hpp: connections_on_port) and ends any whose request has not arrived
// whole within the deadline of its connection, or of the end of its last answer (keep-alive); a
// connection being answered (a handler running, an event stream) is never ended by it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

namespace gpsemu::ui {

class RequestDeadline {
 public:
  /// Watches the connections on local `port` from its own thread until destroyed.
  RequestDeadline(std::uint16_t port, std::chrono::milliseconds deadline);
  ~RequestDeadline();
  RequestDeadline(const RequestDeadline&) = delete;
  RequestDeadline& operator=(const RequestDeadline&) = delete;

  /// A request of `peer` ("127.0.0.1:50123") arrived whole: its handler runs now.
  void begun(const std::string& peer);
  /// Its answer was written: the next request must come within the deadline from now. True when
  /// this watch had ended the connection (the "answer" is the server's 400 to a request cut short).
  bool done(const std::string& peer);
  /// The server's 400 to a request whose line never came whole has no peer: one of the connections
  /// this watch ended, if any is not accounted yet (true), is taken as that one.
  bool claim_ended();
  /// Ends `peer`'s connection once its answer is written (a refused body: the rest is not read).
  void close_after_answer(const std::string& peer);
  /// Connections ended because their request was not whole in time.
  [[nodiscard]] std::uint64_t closed() const { return closed_.load(std::memory_order_relaxed); }

 private:
  struct Connection {
    int fd = -1;
    std::chrono::steady_clock::time_point since;  ///< seen first, or its last answer written
    bool answering = false;
    bool close_after = false;  ///< end it once its answer is written
    bool ended = false;        ///< ended by this watch: not whole in time
    int unseen = 0;  ///< looks at the descriptors since it was last seen
  };
  void run();
  void look(std::chrono::steady_clock::time_point now);

  std::uint16_t port_;
  std::chrono::milliseconds deadline_;
  std::mutex mutex_;
  std::condition_variable stop_wait_;
  bool stopping_ = false;
  std::unordered_map<std::string, Connection> connections_;  ///< by peer
  std::atomic<std::uint64_t> closed_{0};
  std::atomic<std::uint64_t> unclaimed_{0};  ///< ended, their server's answer not yet seen
  std::thread thread_;  ///< last: started once the rest is built
};

}  // namespace gpsemu::ui
