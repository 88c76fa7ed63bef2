#include "emulator/ui/http_server.hpp"

#include <httplib.h>

#include <cctype>
#include <charconv>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <vector>
#include <random>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "emulator/faults/control.hpp"
#include "emulator/faults/json_shape.hpp"
#include "emulator/ui/assets.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu::ui {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kTimeoutS = 2;  ///< read, write and keep-alive timeouts (seconds)
constexpr int kSendBufferBytes = 32 * 1024;  ///< each connection's (the kernel doubles it)
constexpr int kListenBacklog = 256;

/// 32 hex digits from the system's random source.
std::string random_token() {
  std::random_device device;
  std::string out;
  for (int k = 0; k < 4; ++k) out += fmt::format("{:08x}", device());
  return out;
}

/// Requests that come to a loopback bind name it: 127.0.0.1:PORT, localhost:PORT or [::1]:PORT
/// (a page of another site whose name resolves to 127.0.0.1 does not: DNS rebinding).
bool loopback_host_header(const std::string& host, std::uint16_t port) {
  const std::string p = fmt::format(":{}", port);
  for (const char* name : {"127.0.0.1", "localhost", "[::1]"}) {
    if (host == name || host == name + p) return true;
  }
  return false;
}

/// "application/json", in any case, with or without parameters ("; charset=utf-8"); not
/// "application/jsonfoo".
bool json_content_type(std::string_view value) {
  std::string_view type = value.substr(0, value.find(';'));
  while (!type.empty() && (type.back() == ' ' || type.back() == '\t')) type.remove_suffix(1);
  while (!type.empty() && (type.front() == ' ' || type.front() == '\t')) type.remove_prefix(1);
  constexpr std::string_view kJson = "application/json";
  if (type.size() != kJson.size()) return false;
  for (std::size_t k = 0; k < kJson.size(); ++k) {
    if (std::tolower(static_cast<unsigned char>(type[k])) != kJson[k]) return false;
  }
  return true;
}

}  // namespace

/// What the threads count.
struct HttpServer::Counters {
  std::atomic<std::uint64_t> connections{0}, connections_without_request{0}, requests{0}, malformed{0}, too_large{0},
      refused_token{0}, refused_cross_site{0}, streams_refused{0}, streams_dropped{0}, control_requests{0},
      closed_slow{0}, refused_shape{0};
  std::atomic<int> streams{0};
};

namespace {
thread_local std::uint64_t requests_on_connection = 0;
}

/// httplib's task queue (one task a connection): kWorkers threads, more (up to kMaxWorkers) while
/// connections wait for one, so a flood of idle connections (each held for the keep-alive timeout)
/// drains kMaxWorkers at a time; counts the connections that ended without a request (idle ones
/// closed, and those cut off mid-request).
class HttpServer::CountingPool final : public httplib::TaskQueue {
 public:
  explicit CountingPool(Counters& counters) : counters_(counters) {
    std::lock_guard lock(mutex_);
    for (int k = 0; k < kWorkers; ++k) add_worker();
  }
  void enqueue(std::function<void()> fn) override {
    counters_.connections.fetch_add(1, std::memory_order_relaxed);
    {
      std::lock_guard lock(mutex_);
      jobs_.push_back(std::move(fn));
      if (!stopping_ && idle_ == 0 && threads_.size() < static_cast<std::size_t>(kMaxWorkers)) add_worker();
    }
    ready_.notify_one();
  }
  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    ready_.notify_all();
    for (std::thread& t : threads_) t.join();  // no worker is added once stopping
  }

 private:
  void add_worker() {
    threads_.emplace_back([this] {
      for (;;) {
        std::function<void()> job;
        {
          std::unique_lock lock(mutex_);
          ++idle_;
          ready_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
          --idle_;
          if (jobs_.empty()) return;  // stopping, and every connection handled
          job = std::move(jobs_.front());
          jobs_.pop_front();
        }
        requests_on_connection = 0;
        job();
        if (requests_on_connection == 0) counters_.connections_without_request.fetch_add(1, std::memory_order_relaxed);
      }
    });
  }

  Counters& counters_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> jobs_;
  std::vector<std::thread> threads_;  ///< grows under mutex_; joined by shutdown()
  std::size_t idle_ = 0;
  bool stopping_ = false;
};

HttpServer::HttpServer(HttpSettings settings)
    : settings_(std::move(settings)), counters_(std::make_unique<Counters>()),
      server_(std::make_unique<httplib::Server>()) {
  if (!is_loopback(settings_.host)) token_ = settings_.token ? *settings_.token : random_token();
  if (settings_.token && settings_.token->size() < 8) throw std::invalid_argument("ui-token: expected at least 8 characters");
  if (settings_.token) token_ = settings_.token;
  server_->new_task_queue = [this] { return new CountingPool(*counters_); };
  // Many clients at once (a flood is refused by the server, not by accept() running out of
  // descriptors); a small send buffer, so an event stream nobody reads is found out in seconds.
  (void)posix::raise_open_files_limit();
  server_->set_socket_options([this](int fd) {
    posix::configure_listening_socket(fd, kSendBufferBytes);
    listening_fd_ = fd;
  });
  server_->set_read_timeout(kTimeoutS, 0);
  server_->set_write_timeout(kTimeoutS, 0);
  server_->set_keep_alive_timeout(1);  // an idle connection holds a worker this long (seconds)
  server_->set_keep_alive_max_count(100);
  server_->set_payload_max_length(kMaxBodyBytes);
  server_->set_logger([this](const httplib::Request& req, const httplib::Response& res) {
    // A request cut short by the deadline is counted there (closed_slow), not as a request.
    if (deadline_ && (req.remote_addr.empty() ? res.status == 400 && deadline_->claim_ended()
                                              : deadline_->done(posix::host_port(req.remote_addr, static_cast<std::uint16_t>(req.remote_port))))) {
      return;
    }
    ++requests_on_connection;
    counters_->requests.fetch_add(1, std::memory_order_relaxed);
    if (res.status == 400 || res.status == 414 || res.status == 431) counters_->malformed.fetch_add(1, std::memory_order_relaxed);
    if (res.status == 413) counters_->too_large.fetch_add(1, std::memory_order_relaxed);
  });
  routes();
  const int bound = settings_.port == 0 ? server_->bind_to_any_port(settings_.host)
                                        : (server_->bind_to_port(settings_.host, settings_.port) ? settings_.port : -1);
  if (bound <= 0) {
    throw std::runtime_error(fmt::format("ui {}:{}: cannot listen (in use, or not an address of this machine)",
                                         settings_.host, settings_.port));
  }
  port_ = static_cast<std::uint16_t>(bound);
  deadline_ = std::make_unique<RequestDeadline>(port_, std::chrono::seconds(kRequestTimeoutS));
  // httplib listens with 5 slots: room for a page's burst of connections and for floods.
  if (listening_fd_ >= 0) posix::set_listen_backlog(listening_fd_, kListenBacklog);
}

void HttpServer::serve(Hub& hub) {
  hub_ = &hub;
  thread_ = std::thread([this] { server_->listen_after_bind(); });
}

HttpServer::~HttpServer() {
  if (hub_ == nullptr) return;  // bound, never served
  hub_->close();  // event streams waiting for an epoch end now
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

std::string HttpServer::url() const {
  const std::string host = settings_.host.find(':') != std::string::npos ? "[" + settings_.host + "]" : settings_.host;
  return fmt::format("http://{}:{}/{}", host == "0.0.0.0" || host == "[::]" ? "HOST" : host, port_,
                     token_ ? "#token=" + *token_ : std::string());
}

HttpServer::Stats HttpServer::stats() const {
  const Counters& c = *counters_;
  const auto get = [](const std::atomic<std::uint64_t>& a) { return a.load(std::memory_order_relaxed); };
  Stats s{get(c.connections),  get(c.connections_without_request), get(c.requests),        get(c.malformed),
          get(c.too_large),    get(c.refused_token),               get(c.refused_cross_site), get(c.streams_refused),
          get(c.streams_dropped), get(c.control_requests), get(c.closed_slow), get(c.refused_shape)};
  if (deadline_) s.closed_slow += deadline_->closed();
  return s;
}

std::string HttpServer::summary() const {
  const Stats s = stats();
  return fmt::format("bench view: {} connections, {} requests ({} fault requests); refused: {} malformed, {} too large, "
                     "{} without the token, {} cross-site, {} JSON too deep or with a key twice, {} event streams over {}; "
                     "closed: {} connections without a request, {} slow requests (not whole within {} s), {} event "
                     "streams not reading",
                     s.connections, s.requests, s.control_requests, s.malformed, s.too_large, s.refused_token,
                     s.refused_cross_site, s.refused_shape, s.streams_refused, kMaxStreams, s.connections_without_request,
                     s.closed_slow, kRequestTimeoutS, s.streams_dropped);
}

void HttpServer::routes() {
  httplib::Server& srv = *server_;
  // Every request: on a loopback bind, only a Host naming it (a rebinding site's name is refused).
  srv.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    deadline_->begun(posix::host_port(req.remote_addr, static_cast<std::uint16_t>(req.remote_port)));
    if (!token_ && !loopback_host_header(req.get_header_value("Host"), port_)) {
      counters_->refused_cross_site.fetch_add(1, std::memory_order_relaxed);
      res.status = 403;
      res.set_content("Host must be 127.0.0.1, localhost or [::1] with this port\n", "text/plain");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  for (const Asset& asset : assets()) {
    srv.Get(std::string(asset.path), [&asset](const httplib::Request&, httplib::Response& res) {
      res.set_content(asset.body.data(), asset.body.size(), std::string(asset.content_type).c_str());
      res.set_header("Cache-Control", "no-cache");
      res.set_header("X-Content-Type-Options", "nosniff");
    });
  }
  srv.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
    nlohmann::json info = nlohmann::json::parse(hub_->info_json());
    info["token_required"] = token_.has_value();
    res.set_content(info.dump(), "application/json");
  });
  srv.Get("/api/server", [this](const httplib::Request&, httplib::Response& res) {
    const Stats s = stats();
    res.set_content(nlohmann::json{{"connections", s.connections},
                                   {"connections_without_request", s.connections_without_request},
                                   {"requests", s.requests},
                                   {"malformed", s.malformed},
                                   {"too_large", s.too_large},
                                   {"refused_token", s.refused_token},
                                   {"refused_cross_site", s.refused_cross_site},
                                   {"streams_refused", s.streams_refused},
                                   {"streams_dropped", s.streams_dropped},
                                   {"streams_open", counters_->streams.load()},
                                   {"control_requests", s.control_requests},
                                   {"closed_slow", s.closed_slow},
                                   {"refused_shape", s.refused_shape},
                                   {"late_epochs", hub_->late_epochs().load()}}
                        .dump(),
                    "application/json");
  });
  srv.Get("/api/events", [this](const httplib::Request& req, httplib::Response& res) {
    std::size_t i = 0;
    if (req.has_param("receiver")) {
      const std::string text = req.get_param_value("receiver");
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), i);
      if (ec != std::errc() || end != text.data() + text.size() || i >= hub_->receivers()) {
        res.status = 400;
        res.set_content(fmt::format("receiver: expected 0..{}\n", hub_->receivers() - 1), "text/plain");
        return;
      }
    }
    if (counters_->streams.fetch_add(1) >= kMaxStreams) {
      counters_->streams.fetch_sub(1);
      counters_->streams_refused.fetch_add(1, std::memory_order_relaxed);
      res.status = 503;
      res.set_content(fmt::format("at most {} pages at once\n", kMaxStreams), "text/plain");
      return;
    }
    hub_->watch(i, +1);
    res.set_header("Cache-Control", "no-cache");
    auto last = std::make_shared<std::uint64_t>(0);
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, i, last](std::size_t, httplib::DataSink& sink) {
          if (hub_->closed()) {
            sink.done();
            return true;
          }
          const Hub::Published p = hub_->wait_after(i, *last, std::chrono::seconds(1));
          std::string chunk = ": waiting for an epoch\n\n";
          if (p.json) {
            *last = p.epoch;
            chunk = "data: " + *p.json + "\n\n";
          }
          const auto begin = Clock::now();
          if (sink.write(chunk.data(), chunk.size())) return true;
          // A write that failed after waiting out the write timeout: the page did not read.
          if (Clock::now() - begin >= std::chrono::milliseconds(kTimeoutS * 900)) {
            counters_->streams_dropped.fetch_add(1, std::memory_order_relaxed);
          }
          return false;
        },
        [this, i](bool) {
          hub_->watch(i, -1);
          counters_->streams.fetch_sub(1);
        });
  });
  srv.Post("/api/control", [this](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
    // Everything the headers tell is checked before a byte of the body is read.
    const auto refuse = [this, &req, &res](int status, std::string_view message) {
      deadline_->close_after_answer(posix::host_port(req.remote_addr, static_cast<std::uint16_t>(req.remote_port)));
      res.status = status;
      res.set_header("Connection", "close");
      res.set_content(faults::control_error(message), "application/json");
    };
    if (!json_content_type(req.get_header_value("Content-Type"))) {
      counters_->refused_cross_site.fetch_add(1, std::memory_order_relaxed);
      return refuse(415, "expected Content-Type: application/json");
    }
    if (token_ && req.get_header_value("X-Gpsemu-Token") != *token_) {
      counters_->refused_token.fetch_add(1, std::memory_order_relaxed);
      return refuse(403, "this bind needs the token printed at start (header X-Gpsemu-Token)");
    }
    // A browser names the page's origin: this server's (as the Host it asked), or on loopback any
    // of its loopback names with this port.
    const std::string origin = req.get_header_value("Origin");
    const bool same_origin = origin.empty() || origin == "http://" + req.get_header_value("Host") ||
                             (!token_ && origin.rfind("http://", 0) == 0 && loopback_host_header(origin.substr(7), port_));
    if (!same_origin) {
      counters_->refused_cross_site.fetch_add(1, std::memory_order_relaxed);
      return refuse(403, "a request from another origin");
    }
    // The body, whatever its framing (Content-Length, chunked), at most kMaxBodyBytes and whole
    // within kBodyTimeoutS.
    std::string body;
    bool too_large = false, too_slow = false;
    const auto begin = Clock::now();
    const bool read = reader([&](const char* data, std::size_t length) {
      if (body.size() + length > kMaxBodyBytes) return !(too_large = true);
      if (Clock::now() - begin > std::chrono::seconds(kBodyTimeoutS)) return !(too_slow = true);
      body.append(data, length);
      return true;
    });
    // (413 and 400 are counted by the logger, as every answer with them.)
    if (too_large || (!read && res.status == 413)) {
      return refuse(413, fmt::format("a body over {} bytes", kMaxBodyBytes));
    }
    if (too_slow) {
      counters_->closed_slow.fetch_add(1, std::memory_order_relaxed);
      return refuse(408, fmt::format("the body did not arrive whole within {} s", kBodyTimeoutS));
    }
    if (!read) {
      return refuse(400, "the body could not be read");
    }
    if (const std::optional<std::string> problem = faults::json_shape_problem(body)) {
      counters_->refused_shape.fetch_add(1, std::memory_order_relaxed);
      res.status = 422;
      res.set_content(faults::control_error(fmt::format("refused before parsing: {}", *problem)), "application/json");
      return;
    }
    counters_->control_requests.fetch_add(1, std::memory_order_relaxed);
    const std::optional<std::string> answer = hub_->request(std::move(body), std::chrono::seconds(3));
    if (!answer) {
      res.status = 503;
      res.set_content(faults::control_error("the epoch loop did not take the request (stopping?)"), "application/json");
      return;
    }
    const bool error = answer->rfind(R"({"class":"ERROR")", 0) == 0;
    res.status = error ? 400 : 200;
    res.set_content(*answer, "application/json");
  });
}

}  // namespace gpsemu::ui
