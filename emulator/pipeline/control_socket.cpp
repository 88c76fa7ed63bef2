#include "emulator/pipeline/control_socket.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <spdlog/spdlog.h>

#include "emulator/faults/json_shape.hpp"
#include "transport/posix/errors.hpp"
#include "transport/posix/sockets.hpp"

namespace gpsemu {
namespace {

std::vector<faults::FaultTimeline*> timelines_of(ChannelSet& channels) {
  std::vector<faults::FaultTimeline*> out;
  for (std::size_t i = 0; i < channels.size(); ++i) out.push_back(&channels.channel(i).faults());
  return out;
}

posix::UnixLineServer::Settings settings(std::chrono::milliseconds idle_timeout) {
  const double idle_s = std::chrono::duration<double>(idle_timeout).count();
  return {{faults::control_error(fmt::format("too many control clients (at most {}; an idle one is closed after {:g} s)",
                                             posix::UnixLineServer::kMaxClients, idle_s)),
           faults::control_error(
               fmt::format("line longer than {} bytes: ignored to its end", posix::UnixLineServer::kMaxLineBytes)),
           faults::control_error(fmt::format("closed: no request for {:g} s (--control-idle-timeout)", idle_s)),
           faults::control_error(fmt::format("closed: every slot is taken and this client sent no request for {} s",
                                             posix::UnixLineServer::kEvictAfter.count() / 1000))},
          idle_timeout};
}

/// The server for `spec`: a Unix socket, or a TCP port (its real port in its name when 0 was asked).
posix::UnixLineServer make_server(const std::string& spec, std::chrono::milliseconds idle_timeout) {
  if (spec.rfind("tcp:", 0) != 0) return posix::UnixLineServer(spec, settings(idle_timeout));
  const posix::Endpoint e = posix::parse_endpoint(spec.substr(4));
  posix::SocketRequest request;
  request.host = e.host;
  request.port = e.port;
  request.context = fmt::format("control socket {}: cannot listen", spec);
  posix::UniqueFd fd = posix::listen_tcp(request, 8);
  const std::uint16_t port = posix::bound_port(fd.get());
  return posix::UnixLineServer(std::move(fd), "tcp:" + posix::host_port(e.host, port), settings(idle_timeout));
}

constexpr std::string_view kErrorClass = R"({"class":"ERROR")";

}  // namespace

ControlSocket::ControlSocket(const std::string& spec, ChannelSet& channels, std::chrono::milliseconds idle_timeout)
    : control_(timelines_of(channels)), receivers_(channels.size()), server_(make_server(spec, idle_timeout)) {
  if (idle_timeout <= std::chrono::milliseconds::zero()) return;
  idle_timer_.reset(::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC));
  if (!idle_timer_.valid()) throw std::runtime_error(fmt::format("control socket {}: timerfd: {}", spec, posix::errno_text(errno)));
  const auto period = std::max<std::chrono::nanoseconds>(idle_timeout / 4, std::chrono::milliseconds(100));
  itimerspec every{};
  every.it_interval.tv_sec = static_cast<time_t>(std::chrono::duration_cast<std::chrono::seconds>(period).count());
  every.it_interval.tv_nsec = static_cast<long>((period % std::chrono::seconds(1)).count());
  every.it_value = every.it_interval;
  (void)::timerfd_settime(idle_timer_.get(), 0, &every, nullptr);
}

void ControlSocket::fds(std::vector<int>& out) const {
  server_.fds(out);
  if (idle_timer_.valid()) out.push_back(idle_timer_.get());
}

void ControlSocket::service() {
  if (idle_timer_.valid()) {
    std::uint64_t expirations = 0;
    (void)!::read(idle_timer_.get(), &expirations, sizeof expirations);  // re-arm its readiness
  }
  server_.service([this](std::string_view line, std::optional<std::int64_t>& watch) {
    std::string answer = this->answer(line, watch);
    if (answer.rfind(kErrorClass, 0) == 0) {
      ++error_answers_;
      log_limited(error_log_, spdlog::level::warn, "control socket {}: error answer to {:?}: {}", server_.path(),
                             line.substr(0, 200), answer);  // the client's bytes escaped
    }
    return answer;
  });
  log_drops();
}

std::string ControlSocket::answer(std::string_view line, std::optional<std::int64_t>& watch) {
  // The shape check first (control_ refuses and counts it): nothing unchecked reaches a parser.
  if (line.find("\"watch\"") == std::string_view::npos || faults::json_shape_problem(line)) return control_.handle(line);
  const nlohmann::json message = nlohmann::json::parse(line, nullptr, false);
  if (!message.is_object() || !message.contains("watch")) return control_.handle(line);
  std::int64_t which = -1;
  if (const auto it = message.find("receiver"); it != message.end() && !(it->is_string() && *it == "all")) {
    if (!it->is_number_integer() || it->get<std::int64_t>() < 0 || it->get<std::uint64_t>() >= receivers_) {
      return faults::control_error(
          fmt::format("receiver: expected an index 0..{} or \"all\", got {}", receivers_ - 1, it->dump()));
    }
    which = it->get<std::int64_t>();
  }
  watch = which;
  return nlohmann::json{{"class", "WATCH"}, {"receiver", which < 0 ? nlohmann::json("all") : nlohmann::json(which)},
                        {"lines", "one EPOCH object a receiver an epoch (docs/ui.md)"}}
      .dump();
}

void ControlSocket::log_drops() {
  const posix::UnixLineServer::Stats& s = server_.stats();
  const auto more = [](std::uint64_t now, std::uint64_t before) { return now - before; };
  const std::uint64_t refused = more(s.clients_refused, logged_.clients_refused);
  const std::uint64_t idle = more(s.clients_idle_closed, logged_.clients_idle_closed);
  const std::uint64_t not_reading = more(s.clients_not_reading, logged_.clients_not_reading);
  const std::uint64_t too_long = more(s.lines_too_long, logged_.lines_too_long);
  const std::uint64_t evicted = more(s.clients_evicted, logged_.clients_evicted);
  const std::uint64_t shape = control_.refused_shape() - logged_shape_;
  if (refused + idle + not_reading + too_long + evicted + shape == 0) return;
  // Only what happened: "1 client(s) refused (already 8 connected); 2 closed idle (no request for 30 s)".
  std::string what;
  const auto add = [&what](std::uint64_t n, std::string text) {
    if (n > 0) what += (what.empty() ? "" : "; ") + fmt::format("{} {}", n, text);
  };
  add(refused, fmt::format("client(s) refused (already {} connected)", posix::UnixLineServer::kMaxClients));
  add(idle, fmt::format("closed idle (no request for {:g} s)", std::chrono::duration<double>(server_.idle_timeout()).count()));
  add(not_reading, "dropped (not reading their answers)");
  add(too_long, "line(s) too long");
  add(evicted, fmt::format("closed for a newcomer (every slot taken, no request for {} s)",
                           posix::UnixLineServer::kEvictAfter.count() / 1000));
  add(shape, "request(s) refused before parsing (JSON nested too deep or a key twice)");
  if (log_limited(drop_log_, spdlog::level::warn, "control socket {}: {}", server_.path(), what)) {
    logged_ = s;
    logged_shape_ = control_.refused_shape();
  }
}

std::string ControlSocket::summary() const {
  const posix::UnixLineServer::Stats& s = server_.stats();
  return fmt::format("control socket {}: {} requests answered ({} errors, {} refused before parsing); {} clients "
                     "connected, {} refused (too many), {} closed for a newcomer, {} closed idle, {} dropped not "
                     "reading; {} lines too long, {} empty lines skipped; held to {} requests a second {} times",
                     server_.path(), s.lines_answered, error_answers_, control_.refused_shape(), s.clients_accepted,
                     s.clients_refused, s.clients_evicted, s.clients_idle_closed, s.clients_not_reading,
                     s.lines_too_long, s.empty_lines, posix::UnixLineServer::kLinesPerSecond, s.clients_throttled);
}

std::string control_request(const std::string& spec, std::string_view line, std::chrono::milliseconds timeout) {
  if (spec.rfind("tcp:", 0) == 0) {
    const posix::Endpoint e = posix::parse_endpoint(spec.substr(4));
    return posix::tcp_request(e.host, e.port, line, timeout);
  }
  return posix::unix_request(spec.rfind("unix:", 0) == 0 ? spec.substr(5) : spec, line, timeout);
}

void control_watch(const std::string& spec, std::string_view line, std::chrono::milliseconds timeout,
                   const posix::LineSink& sink) {
  if (spec.rfind("tcp:", 0) == 0) {
    const posix::Endpoint e = posix::parse_endpoint(spec.substr(4));
    posix::tcp_exchange(e.host, e.port, line, timeout, sink);
    return;
  }
  posix::unix_exchange(spec.rfind("unix:", 0) == 0 ? spec.substr(5) : spec, line, timeout, sink);
}

}  // namespace gpsemu
