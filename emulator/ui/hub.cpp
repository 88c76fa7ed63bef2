#include "emulator/ui/hub.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "emulator/faults/catalogue.hpp"
#include "transport/posix/errors.hpp"
#include "transport/pty_output.hpp"
#include "transport/tcp_output.hpp"

namespace gpsemu::ui {
namespace {

using nlohmann::json;

std::vector<faults::FaultTimeline*> timelines_of(ChannelSet& channels) {
  std::vector<faults::FaultTimeline*> out;
  for (std::size_t i = 0; i < channels.size(); ++i) out.push_back(&channels.channel(i).faults());
  return out;
}

/// The page's fault forms: every kind of the catalogue with its parameters and their help.
json catalogue_json() {
  json kinds = json::array();
  for (const faults::KindInfo& k : faults::catalogue()) {
    json parameters = json::array();
    for (const std::string_view key : faults::parameters_of(k.kind)) {
      const faults::ParameterInfo* info = faults::parameter_info(key);
      parameters.push_back({{"key", std::string(key)}, {"help", info ? std::string(info->help) : std::string()}});
    }
    for (const std::string_view key : {std::string_view("duration"), std::string_view("where")}) {
      const faults::ParameterInfo* info = faults::parameter_info(key);
      parameters.push_back({{"key", std::string(key)}, {"help", info ? std::string(info->help) : std::string()}});
    }
    kinds.push_back({{"fault", std::string(k.name)}, {"parameters", parameters}});
  }
  return kinds;
}

std::string fmt_optional(const std::optional<double>& value, const char* format_unit) {
  return value ? fmt::format(fmt::runtime(format_unit), *value) : std::string("-");
}

}  // namespace

Hub::Hub(ChannelSet& channels, std::chrono::nanoseconds status_every)
    : channels_(channels), control_(timelines_of(channels)), status_every_(status_every), receivers_(channels.size()) {
  wake_.reset(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC));
  if (!wake_.valid()) throw std::runtime_error(fmt::format("bench view: eventfd: {}", posix::errno_text(errno)));
  json names = json::array();
  for (std::size_t i = 0; i < channels.size(); ++i) {
    const Channel& ch = channels.channel(i);
    const bool plain = ch.protocol().receiver_name().empty();  // an NMEA source; else "(u-blox)"
    names.push_back(fmt::format("receiver {}{}", i, plain ? "" : " (" + ch.protocol().name() + ")"));
  }
  info_json_ = json{{"receivers", channels.size()}, {"names", names}, {"faults", catalogue_json()}}.dump();
}

Hub::~Hub() { close(); }

void Hub::epoch(const EpochView& view) {
  Receiver& r = receivers_[view.receiver];
  ++r.epochs;
  r.error = epoch_error(view);
  r.hdop = view.fix.hdop;
  r.satellites_used = view.fix.satellites_used;
  r.satellites_in_view = view.fix.satellites_in_view;
  r.quality = view.fix.quality;
  r.outputs = view.outputs;
  // Bytes a second over windows of at least a second of epoch time.
  if (view.outputs) {
    std::uint64_t bytes = 0;
    for (const auto& o : *view.outputs) bytes += o->stats().bytes_written;
    if (r.window_start == UtcNs{}) {
      r.window_start = view.t;
      r.window_bytes = bytes;
    } else if (const double span_s = std::chrono::duration<double>(view.t - r.window_start).count(); span_s >= 1.0) {
      r.bytes_per_s = static_cast<double>(bytes - r.window_bytes) / span_s;
      r.window_start = view.t;
      r.window_bytes = bytes;
    }
  }
  if (status_every_ > std::chrono::nanoseconds::zero()) {
    const auto now = std::chrono::steady_clock::now();
    if (r.last_status_line == std::chrono::steady_clock::time_point{}) r.last_status_line = now;
    if (now - r.last_status_line >= status_every_) {
      r.last_status_line = now;
      log_status_line(view.receiver, r, view.channel);
    }
  }
  const std::size_t watchers = control_socket_ ? control_socket_->watchers() : 0;
  int pages = 0;
  {
    std::lock_guard lock(mutex_);
    pages = r.page_clients;
  }
  if (pages == 0 && watchers == 0) return;
  SnapshotContext context;
  context.receivers = receivers_.size();
  context.epoch = r.epochs;
  context.bytes_per_s = r.bytes_per_s;
  context.late_epochs = late_epochs_.load(std::memory_order_relaxed);
  context.page_clients = page_clients();
  context.watch_clients = watchers;
  auto text = std::make_shared<const std::string>(epoch_json(view, r.error, context));
  if (watchers != 0) control_socket_->push(*text, view.receiver);
  if (pages == 0) return;
  {
    std::lock_guard lock(mutex_);
    r.published = {r.epochs, std::move(text)};
  }
  published_.notify_all();
}

void Hub::log_status_line(std::size_t i, const Receiver& r, const Channel& channel) const {
  std::string active;
  for (const faults::FaultTimeline::Entry& e : channel.faults().entries()) {
    if (e.active) active += (active.empty() ? "" : ",") + std::string(faults::kind_name(e.fault.kind()));
  }
  spdlog::info("{}status: epoch {} ({:.1f} s), fix {}, {} of {} satellites used, HDOP {:.2f}, error against the truth "
               "{} horizontal {} vertical; {:.0f} bytes/s; {} late epochs; faults {}; {} page(s) open",
               receivers_.size() > 1 ? fmt::format("receiver {}: ", i) : std::string(), r.epochs,
               channel.faults().last_epoch().since_s, quality_name(r.quality), r.satellites_used, r.satellites_in_view,
               r.hdop, fmt_optional(r.error.horizontal_m(), "{:.2f} m"), fmt_optional(r.error.vertical_m(), "{:+.2f} m"),
               r.bytes_per_s, late_epochs_.load(std::memory_order_relaxed), active.empty() ? "none" : active,
               page_clients());
}

std::string Hub::status_extra(std::size_t i) const {
  const Receiver& r = receivers_.at(i);
  const auto rounded = [](const std::optional<double>& v) { return v ? json(std::round(*v * 1000.0) / 1000.0) : json(nullptr); };
  json outputs = json::array();
  if (r.outputs) {
    for (const auto& o : *r.outputs) {
      json entry{{"name", o->describe()}, {"bytes_written", o->stats().bytes_written}, {"clients", nullptr}};
      if (const auto clients = o->clients_connected()) entry["clients"] = *clients;
      outputs.push_back(std::move(entry));
    }
  }
  int pages = 0;
  {
    std::lock_guard lock(mutex_);
    pages = r.page_clients;
  }
  return json{{"hdop", std::round(r.hdop * 100.0) / 100.0},
              {"satellites_in_view", r.satellites_in_view},
              {"error_horizontal_m", rounded(r.error.horizontal_m())},
              {"error_vertical_m", rounded(r.error.vertical_m())},
              {"outputs", outputs},
              {"page_clients", pages},
              {"watch_clients", control_socket_ ? control_socket_->watchers() : 0},
              {"late_epochs", late_epochs_.load(std::memory_order_relaxed)}}
      .dump(-1, ' ', false, json::error_handler_t::replace);
}

void Hub::fds(std::vector<int>& out) const { out.push_back(wake_.get()); }

void Hub::service() {
  std::uint64_t count = 0;
  (void)!::read(wake_.get(), &count, sizeof count);
  // A few requests a call, so a burst of them is spread over the loop's wake-ups between epochs
  // instead of making one epoch late; the rest wake the loop again.
  std::deque<std::shared_ptr<Pending>> work;
  bool more = false;
  {
    std::lock_guard lock(mutex_);
    while (!pending_.empty() && work.size() < kRequestsPerService) {
      work.push_back(std::move(pending_.front()));
      pending_.pop_front();
    }
    more = !pending_.empty();
  }
  for (const auto& p : work) p->answer.set_value(control_.handle(p->line));
  if (more) {
    const std::uint64_t one = 1;
    (void)!::write(wake_.get(), &one, sizeof one);
  }
}

Hub::Published Hub::wait_after(std::size_t i, std::uint64_t after, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  const Receiver& r = receivers_.at(i);
  (void)published_.wait_for(lock, timeout, [&] { return closed_ || (r.published.json && r.published.epoch > after); });
  if (!r.published.json || r.published.epoch <= after) return {after, nullptr};
  return r.published;
}

void Hub::watch(std::size_t i, int delta) {
  std::lock_guard lock(mutex_);
  Receiver& r = receivers_.at(i);
  // A page that comes after nobody watched starts at the next epoch, not at an old one.
  if (r.page_clients == 0 && delta > 0) r.published = {};
  r.page_clients += delta;
}

std::size_t Hub::page_clients() const {
  std::lock_guard lock(mutex_);
  std::size_t n = 0;
  for (const Receiver& r : receivers_) n += static_cast<std::size_t>(r.page_clients);
  return n;
}

std::optional<std::string> Hub::request(std::string line, std::chrono::milliseconds timeout) {
  auto p = std::make_shared<Pending>();
  p->line = std::move(line);
  std::future<std::string> answer = p->answer.get_future();
  {
    std::lock_guard lock(mutex_);
    if (closed_) return std::nullopt;
    pending_.push_back(p);
  }
  const std::uint64_t one = 1;
  (void)!::write(wake_.get(), &one, sizeof one);
  if (answer.wait_for(timeout) != std::future_status::ready) return std::nullopt;
  return answer.get();
}

void Hub::close() {
  std::deque<std::shared_ptr<Pending>> left;
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
    left.swap(pending_);
  }
  for (const auto& p : left) p->answer.set_value(faults::control_error("gpsemu is stopping"));
  published_.notify_all();
}

bool Hub::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

}  // namespace gpsemu::ui
