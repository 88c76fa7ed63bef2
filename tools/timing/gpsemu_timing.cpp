// gpsemu-timing: measures a receiver's output timing the way a client sees it. Reads NMEA from
// one or many outputs at once -- ptys or serial devices, TCP servers, UDP datagrams -- stamps the
// arrival of each epoch's first bytes, and compares it with the epoch's ideal time: its UTC time
// field + latency. Reports median offset, p99 and max deviation, and missing/repeated epochs, per
// output and over all outputs x epochs, and names the worst output.
//
// Clocks: a UDP datagram is stamped by the kernel when it was received (SO_TIMESTAMPNS,
// CLOCK_REALTIME), so the figure does not include this tool's own scheduling; pty/serial/tcp
// bytes are stamped with CLOCK_REALTIME just before the read() that returns them (user space:
// includes this tool's wake-up latency). A sentence split over two reads is stamped with the
// read that brought its '$'.
//
// Epochs: a new epoch starts at a timed sentence (RMC or GGA) whose time differs from the current
// epoch's, or at a repeat of the current epoch's first timed sentence type (the same epoch sent
// again: "repeated"). A UDP datagram is always one epoch. On a stream the first epoch is not
// counted: it may be cut in half, or be the one the device held before this tool opened it.
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "nmea/parse.hpp"
#include "tools/timing/timing_figures.hpp"
#include "tools/timing/timing_inputs.hpp"
#include "transport/posix/errors.hpp"
#include "transport/posix/realtime.hpp"
#include "transport/posix/sockets.hpp"
#include "transport/posix/wall_clock.hpp"

using namespace gpsemu::timing;

namespace {

double realtime_s() { return gpsemu::posix::to_unix_seconds(gpsemu::posix::wall_clock_now()); }

/// One epoch as one output delivered it.
struct EpochRecord {
  double epoch_tod_s;   ///< the epoch's UTC time of day
  double arrival_s;     ///< first-byte arrival, Unix seconds
  double deviation_ms;  ///< arrival - (epoch + latency)
};

/// One output being measured: its descriptor, parser state and the epochs it delivered.
struct Output {
  Kind kind = Kind::device;
  std::string name;  ///< "udp:127.0.0.1:7000", "/tmp/gps0", "tcp:127.0.0.1:10110"
  int fd = -1;
  bool closed = false;
  gpsemu::nmea::StreamReader reader;
  // Stream stamping: the read time of the chunk holding the '$' of a sentence still incomplete.
  std::optional<double> partial_stamp;
  // Epoch tracking.
  std::optional<double> current_epoch_s;
  std::string current_first_type;  ///< the first timed sentence type of the current epoch
  bool skip_first = true;          ///< streams: the first epoch is not counted
  double period_s = 0.0;           ///< smallest step seen between epochs
  std::vector<EpochRecord> epochs;
  long missing = 0, repeated = 0, out_of_order = 0;
  std::uint64_t kernel_dropped = 0;   ///< UDP: datagrams our socket buffer dropped (SO_RXQ_OVFL)
  gpsemu::posix::DropCounter kernel_drops;
  std::uint64_t user_stamped = 0;     ///< UDP datagrams without a kernel stamp (stamped in user space)
  double last_data_s = 0.0;
};

class Meter {
 public:
  explicit Meter(double latency_s) : latency_s_(latency_s) {}

  /// Bytes read from a stream output at `stamp` (Unix seconds).
  void stream_bytes(Output& o, std::string_view bytes, double stamp) {
    const std::optional<double> carried = o.partial_stamp;
    bool first = true;
    for (const auto& s : o.reader.feed(bytes)) {
      sentence(o, s, first && carried ? *carried : stamp, false);
      first = false;
    }
    // Does this chunk end inside a sentence? Then its '$' came in this chunk, or earlier.
    const auto end = bytes.find_last_of("\r\n");
    const auto dollar = bytes.rfind('$');
    if (dollar != std::string_view::npos && (end == std::string_view::npos || dollar > end)) {
      o.partial_stamp = stamp;
    } else if (end != std::string_view::npos) {
      o.partial_stamp.reset();
    }
  }

  /// One datagram (one whole epoch) received at `stamp`.
  void datagram(Output& o, std::string_view bytes, double stamp) {
    bool first = true;
    for (const auto& s : o.reader.feed(bytes)) {
      sentence(o, s, stamp, first);
      first = false;
    }
    if (const auto last = o.reader.finish()) sentence(o, *last, stamp, first);
  }

 private:
  void sentence(Output& o, const gpsemu::nmea::Sentence& s, double stamp, bool new_datagram) {
    std::optional<std::chrono::milliseconds> tod;
    if (s.type == "GGA") {
      if (auto g = gpsemu::nmea::parse_gga(s)) tod = g->time_of_day;
    } else if (s.type == "RMC") {
      if (auto r = gpsemu::nmea::parse_rmc(s)) tod = r->time_of_day;
    }
    if (!tod) return;
    const double epoch_s = static_cast<double>(tod->count()) / 1000.0;
    const bool same_time = o.current_epoch_s && *o.current_epoch_s == epoch_s;
    if (same_time && !new_datagram && s.type != o.current_first_type) return;  // the same epoch goes on
    const std::optional<double> previous = o.current_epoch_s;
    o.current_epoch_s = epoch_s;
    o.current_first_type = s.type;
    if (o.skip_first) {
      o.skip_first = false;
      return;
    }
    if (previous) {
      double step = std::fmod(epoch_s - *previous + 86400.0, 86400.0);
      if (step > 43200.0) {  // backwards
        ++o.out_of_order;
        return;
      }
      if (step == 0.0) {
        ++o.repeated;
        return;
      }
      if (o.period_s == 0.0 || step < o.period_s - 1e-6) o.period_s = step;
      if (step > 1.5 * o.period_s) o.missing += std::lround(step / o.period_s) - 1;
    }
    // The ideal time: the epoch's time of day on the day nearest the arrival.
    const double day0 = std::floor(stamp / 86400.0) * 86400.0;
    double ideal = day0 + epoch_s + latency_s_;
    if (ideal - stamp > 43200.0) ideal -= 86400.0;
    if (stamp - ideal > 43200.0) ideal += 86400.0;
    o.epochs.push_back({epoch_s, stamp, (stamp - ideal) * 1000.0});
  }

  double latency_s_;
};

/// Reads what a stream output has; false once it reached its end (EOF, hang-up, error).
bool read_stream(Output& o, Meter& meter) {
  char buf[8192];
  while (true) {
    const double stamp = realtime_s();
    const ssize_t n = ::read(o.fd, buf, sizeof buf);
    if (n > 0) {
      o.last_data_s = stamp;
      meter.stream_bytes(o, std::string_view(buf, static_cast<std::size_t>(n)), stamp);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return true;
    return false;  // 0: EOF; EIO: the pty's other side is gone
  }
}

/// Receives the datagrams a UDP output has, each stamped by the kernel.
void read_udp(Output& o, Meter& meter) {
  std::array<char, 65536> buf{};
  while (const auto d = gpsemu::posix::receive_datagram(o.fd, buf)) {  // none left: drained
    if (d->drop_counter) o.kernel_dropped += o.kernel_drops.update(*d->drop_counter);
    std::optional<double> stamp;
    if (d->kernel_time) {
      stamp = gpsemu::posix::to_unix_seconds(*d->kernel_time);
    } else {
      stamp = realtime_s();
      ++o.user_stamped;
    }
    o.last_data_s = realtime_s();
    meter.datagram(o, std::string_view(buf.data(), std::min(d->size, buf.size())), *stamp);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gpsemu-timing: first-byte arrival of each epoch against UTC epoch time + latency"};
  std::vector<std::string> devices, tcps, udps;
  std::string csv_path, json_path;
  double latency_s = 0.05, duration_s = 60.0, idle_s = 0.0;
  int count = 1;
  bool per_output = false;
  app.add_option("--device", devices, "pty or serial device to read (e.g. /tmp/gpsemu, /tmp/gps{i}); repeatable");
  app.add_option("--tcp", tcps, "HOST:PORT of a tcp output to read; repeatable");
  app.add_option("--udp", udps,
                 "[HOST:]PORT to bind and receive udp output datagrams on (e.g. 127.0.0.1:{7000+i}); "
                 "stamped with the kernel receive time; repeatable");
  app.add_option("--count", count, "outputs per --device/--tcp/--udp: expands {i} (0..N-1) and {B+i} (default 1)")
      ->check(CLI::Range(1, 65536));
  app.add_option("--latency", latency_s, "the emulator's configured latency, seconds (default 0.05)");
  app.add_option("--duration", duration_s, "how long to measure at most, seconds (default 60)");
  app.add_option("--idle", idle_s,
                 "stop once every output has delivered data and all have been silent this long, seconds "
                 "(default 0: off)");
  app.add_option("--csv", csv_path, "write one line per output and epoch: epoch_time_of_day_s,arrival_unix_s,"
                                    "deviation_ms,output");
  app.add_option("--json", json_path, "write the figures (total, per output, worst output) as JSON");
  app.add_flag("--per-output", per_output, "print one line per output (the default up to 16 outputs)");
  // The reader's own scheduling, so what it measures is the emulator's timing, not its own.
  int priority = 0;
  bool lock_memory = false;
  long timer_slack_ns = 0;
  app.add_option("--realtime-priority", priority,
                 "read at SCHED_FIFO priority N, 1..99 (where not permitted: one message, normal scheduling)")
      ->check(CLI::Range(1, 99));
  app.add_flag("--lock-memory", lock_memory, "mlockall: no page faults while reading");
  app.add_option("--timer-slack", timer_slack_ns, "prctl timer slack, ns (1: minimal; default: the kernel's 50 000)")
      ->check(CLI::Range(1L, 1'000'000'000L));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // A wrong flag or value: one message naming it, status 2 (as gpsemu itself).
    std::fprintf(stderr, "gpsemu-timing: %s\n", e.what());
    return 2;
  }
  if (devices.empty() && tcps.empty() && udps.empty()) {
    std::fprintf(stderr, "gpsemu-timing: give at least one --device, --tcp or --udp\n");
    return 2;
  }

  gpsemu::posix::RealtimeSettings realtime;
  if (priority > 0) realtime.fifo_priority = priority;
  realtime.lock_memory = lock_memory;
  if (timer_slack_ns > 0) realtime.timer_slack_ns = timer_slack_ns;
  for (const std::string& line : gpsemu::posix::apply_realtime_settings(realtime)) {
    std::fprintf(stderr, "gpsemu-timing: %s\n", line.c_str());
  }

  std::vector<Output> outputs;
  try {
    auto add = [&](Kind kind, const std::vector<std::string>& specs) {
      for (const auto& spec : specs) {
        if (count > 1 && !has_template(spec)) {
          throw std::invalid_argument(fmt::format("--count {} needs {{i}} or {{B+i}} in '{}'", count, spec));
        }
        for (int i = 0; i < count; ++i) {
          Output o;
          o.kind = kind;
          const std::string target = expand_template(spec, i);
          o.name = kind == Kind::device ? target : fmt::format("{}:{}", kind_name(kind), target);
          o.skip_first = kind != Kind::udp;
          o.fd = kind == Kind::device ? open_device(target) : kind == Kind::tcp ? open_tcp(target) : open_udp(target);
          outputs.push_back(std::move(o));
        }
      }
    };
    add(Kind::device, devices);
    add(Kind::tcp, tcps);
    add(Kind::udp, udps);
  } catch (const std::exception& e) {
    for (auto& o : outputs) ::close(o.fd);
    std::fprintf(stderr, "gpsemu-timing: %s\n", e.what());
    return 2;
  }

  const int ep = epoll_create1(EPOLL_CLOEXEC);
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u64 = i;
    if (epoll_ctl(ep, EPOLL_CTL_ADD, outputs[i].fd, &ev) != 0) {
      std::fprintf(stderr, "gpsemu-timing: epoll on %s: %s\n", outputs[i].name.c_str(), gpsemu::posix::errno_text(errno).c_str());
      return 2;
    }
  }

  Meter meter(latency_s);
  std::size_t open_outputs = outputs.size();
  const double end = realtime_s() + duration_s;
  std::vector<epoll_event> events(std::min<std::size_t>(outputs.size(), 1024));
  while (open_outputs > 0) {
    const double now = realtime_s();
    if (now >= end) break;
    if (idle_s > 0.0 && std::all_of(outputs.begin(), outputs.end(), [&](const Output& o) {
          return o.closed || (o.last_data_s > 0.0 && now - o.last_data_s >= idle_s);
        })) {
      break;
    }
    const int n = epoll_wait(ep, events.data(), static_cast<int>(events.size()), 100);
    for (int k = 0; k < n; ++k) {
      Output& o = outputs[events[static_cast<std::size_t>(k)].data.u64];
      if (o.closed) continue;
      if (o.kind == Kind::udp) {
        read_udp(o, meter);
      } else if (!read_stream(o, meter)) {
        epoll_ctl(ep, EPOLL_CTL_DEL, o.fd, nullptr);
        o.closed = true;
        --open_outputs;
      }
    }
  }
  ::close(ep);
  for (auto& o : outputs) ::close(o.fd);

  if (!csv_path.empty()) {
    std::ofstream csv(csv_path);
    csv << "epoch_time_of_day_s,arrival_unix_s,deviation_ms,output\n";
    for (const auto& o : outputs) {
      for (const auto& r : o.epochs) {
        csv << fmt::format("{:.3f},{:.6f},{:.3f},{}\n", r.epoch_tod_s, r.arrival_s, r.deviation_ms, o.name);
      }
    }
  }

  // Figures per output and over all outputs x epochs.
  std::vector<double> all_dev;
  std::vector<Figures> per;
  long missing = 0, repeated = 0, out_of_order = 0;
  std::uint64_t kernel_dropped = 0, user_stamped = 0;
  double period_s = 0.0;
  std::size_t silent = 0;
  std::optional<std::size_t> worst;
  gpsemu::nmea::StreamStats reader_total;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& o = outputs[i];
    std::vector<double> dev;
    for (const auto& r : o.epochs) dev.push_back(r.deviation_ms);
    all_dev.insert(all_dev.end(), dev.begin(), dev.end());
    per.push_back(figures_of(dev));
    missing += o.missing;
    repeated += o.repeated;
    out_of_order += o.out_of_order;
    kernel_dropped += o.kernel_dropped;
    user_stamped += o.user_stamped;
    if (o.period_s > 0.0 && (period_s == 0.0 || o.period_s < period_s)) period_s = o.period_s;
    if (dev.empty()) ++silent;
    // The worst output: most missing/repeated epochs, then the largest |deviation|.
    auto badness = [&](std::size_t j) {
      return std::make_pair(outputs[j].missing + outputs[j].repeated + outputs[j].out_of_order,
                            per[j].epochs == 0 ? INFINITY : per[j].abs_max_ms);
    };
    if (!worst || badness(i) > badness(*worst)) worst = i;
    reader_total.sentences_ok += o.reader.stats().sentences_ok;
    reader_total.bad_checksum += o.reader.stats().bad_checksum;
    reader_total.malformed += o.reader.stats().malformed;
    reader_total.garbage_bytes += o.reader.stats().garbage_bytes;
  }
  const Figures total = figures_of(all_dev);
  const bool any_udp = std::any_of(outputs.begin(), outputs.end(), [](const Output& o) { return o.kind == Kind::udp; });
  const bool any_stream = std::any_of(outputs.begin(), outputs.end(), [](const Output& o) { return o.kind != Kind::udp; });
  std::string clock = any_udp ? "udp: kernel receive time (SO_TIMESTAMPNS, CLOCK_REALTIME)" : "";
  if (any_stream) {
    clock += fmt::format("{}pty/serial/tcp: CLOCK_REALTIME at read() (user space)", clock.empty() ? "" : "; ");
  }

  if (!json_path.empty()) {
    nlohmann::json j;
    j["latency_s"] = latency_s;
    j["period_s"] = period_s;
    j["clock"] = clock;
    j["outputs"] = outputs.size();
    j["silent_outputs"] = silent;
    j["total"] = figures_json(total);
    j["total"]["missing"] = missing;
    j["total"]["repeated"] = repeated;
    j["total"]["out_of_order"] = out_of_order;
    j["total"]["kernel_dropped"] = kernel_dropped;
    j["per_output"] = nlohmann::json::array();
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      const auto& o = outputs[i];
      auto f = figures_json(per[i]);
      f["name"] = o.name;
      f["kind"] = kind_name(o.kind);
      f["missing"] = o.missing;
      f["repeated"] = o.repeated;
      f["out_of_order"] = o.out_of_order;
      f["kernel_dropped"] = o.kernel_dropped;
      f["first_epoch_s"] = o.epochs.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.epochs.front().epoch_tod_s);
      f["last_epoch_s"] = o.epochs.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.epochs.back().epoch_tod_s);
      j["per_output"].push_back(f);
    }
    if (worst) j["worst_output"] = outputs[*worst].name;
    std::ofstream(json_path) << j.dump(1) << "\n";
  }

  if (all_dev.empty()) {
    std::fprintf(stderr, "gpsemu-timing: no epochs received\n");
    return 1;
  }
  if (outputs.size() > 1) fmt::print("outputs {} ({} silent); clock: {}\n", outputs.size(), silent, clock);
  else fmt::print("clock: {}\n", clock);
  fmt::print("epochs {} missing {} repeated {} period {:.3f} s\n", total.epochs, missing, repeated, period_s);
  fmt::print("arrival - (epoch + latency): median {:.3f} ms, p99 {:.3f} ms, max {:.3f} ms, min {:.3f} ms\n",
             total.median_ms, total.p99_ms, total.max_ms, total.min_ms);
  fmt::print("|deviation|: p99 {:.3f} ms, max {:.3f} ms\n", total.abs_p99_ms, total.abs_max_ms);
  if (out_of_order > 0 || kernel_dropped > 0 || user_stamped > 0) {
    fmt::print("out of order {}; datagrams dropped by this tool's socket buffers {}; datagrams without a kernel "
               "stamp {}\n", out_of_order, kernel_dropped, user_stamped);
  }
  if (outputs.size() > 1 && worst) {
    const auto& o = outputs[*worst];
    fmt::print("worst output {}: epochs {} missing {} repeated {}, |deviation| p99 {:.3f} ms, max {:.3f} ms\n", o.name,
               per[*worst].epochs, o.missing, o.repeated, per[*worst].abs_p99_ms, per[*worst].abs_max_ms);
  }
  if (outputs.size() > 1 && (per_output || outputs.size() <= 16)) {
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      const auto& o = outputs[i];
      fmt::print("  {}: epochs {} missing {} repeated {}, median {:.3f} ms, p99 {:.3f} ms, max {:.3f} ms\n", o.name,
                 per[i].epochs, o.missing, o.repeated, per[i].median_ms, per[i].p99_ms, per[i].max_ms);
    }
  }
  fmt::print("reader stats: sentences {} bad checksum {} malformed {} garbage bytes {}\n", reader_total.sentences_ok,
             reader_total.bad_checksum, reader_total.malformed, reader_total.garbage_bytes);
  return silent > 0 ? 1 : 0;
}
