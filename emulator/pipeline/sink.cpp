#include "emulator/pipeline/sink.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "emulator/pipeline/serial_line_check.hpp"
#include "transport/tee_output.hpp"

namespace gpsemu {

std::vector<std::unique_ptr<transport::Output>> open_outputs(const OutputSettings& settings) {
  const std::vector<transport::OutputSpec>& specs = settings.outputs;
  // Refuse a serial line that cannot carry the epochs before opening anything.
  std::optional<std::size_t> epoch_bytes;
  for (const auto& spec : specs) {
    if (spec.kind != transport::OutputKind::serial || !settings.widest_epoch_bytes) continue;
    if (!epoch_bytes) epoch_bytes = settings.widest_epoch_bytes();
    check_serial_line_budget(spec, *epoch_bytes, settings.rate_hz);
  }
  std::vector<std::unique_ptr<transport::Output>> outputs;
  for (const auto& spec : specs) {
    outputs.push_back(
        transport::make_output(spec, transport::OutputOptions{.realtime = settings.realtime, .rate_hz = settings.rate_hz}));
  }
  if (settings.tee) outputs.push_back(std::make_unique<transport::TeeOutput>(*settings.tee, settings.realtime));
  return outputs;
}

std::size_t Sink::add(std::vector<std::unique_ptr<transport::Output>> outputs) {
  receivers_.push_back(std::move(outputs));
  return receivers_.size() - 1;
}

void Sink::attach_client_input(std::size_t i, transport::ClientInput* input) {
  for (const auto& out : receivers_.at(i)) out->set_client_input(input);
}

void Sink::prepare(std::size_t i) {
  for (const auto& out : receivers_[i]) out->prepare_epoch();
}

void Sink::service_all() {
  for (const auto& outputs : receivers_) {
    for (const auto& out : outputs) {
      out->service();
      out->answer_clients();
    }
  }
}

bool Sink::none_took_any() const {
  bool failed = false;
  for (const auto& outputs : receivers_) {
    for (const auto& out : outputs) {
      if (out->stats().epochs_written != 0) return false;
      failed = failed || out->stats().epochs_failed != 0;
    }
  }
  return failed;
}

bool Sink::all_gone() const {
  bool any = false;
  for (const auto& outputs : receivers_) {
    for (const auto& out : outputs) {
      if (!out->gone()) return false;
      any = true;
    }
  }
  return any;
}

void Sink::flush() {
  for (const auto& outputs : receivers_) {
    for (const auto& out : outputs) out->flush();
  }
}

void Sink::commit() {
  for (const auto& outputs : receivers_) {
    for (const auto& out : outputs) out->commit();
  }
}

void Sink::list_inputs(std::vector<int>& fds, std::vector<transport::Output*>& owners) const {
  for (const auto& outputs : receivers_) {
    for (const auto& out : outputs) {
      if (out->poll_fd() < 0) continue;
      fds.push_back(out->poll_fd());
      owners.push_back(out.get());
    }
  }
}

transport::SerialOutput* Sink::first_serial() const {
  for (const auto& outputs : receivers_) {
    for (const auto& out : outputs) {
      if (auto* serial = out->serial_line()) return serial;
    }
  }
  return nullptr;
}

std::string Sink::who(std::size_t i) const { return receivers_.size() > 1 ? fmt::format("receiver {}: ", i) : ""; }

void Sink::log_opened(std::size_t i, std::string_view protocol) const {
  for (const auto& out : receivers_.at(i)) spdlog::info("{}{} on {}", who(i), protocol, out->describe());
}

void Sink::log_summary(std::size_t i) const {
  for (const auto& out : receivers_.at(i)) {
    const auto& s = out->stats();
    spdlog::info("{}{}: {} epochs written ({} bytes), {} dropped, {} failed{}{}{}", who(i), out->describe(),
                 s.epochs_written, s.bytes_written, s.epochs_dropped, s.epochs_failed,
                 s.epochs_empty != 0 ? fmt::format(", {} with nothing to send", s.epochs_empty) : "",
                 s.replies_written != 0
                     ? fmt::format("; {} replies to the client ({} bytes)", s.replies_written, s.reply_bytes_written)
                     : "",
                 out->clients_summary());
    if (s.replies_dropped > 0) {
      spdlog::warn("{}{}: answers to clients: {} batches written, {} dropped whole ({} bytes; a batch answers one read "
                   "of a client's): no room for them", who(i), out->describe(), s.replies_written, s.replies_dropped,
                   s.reply_bytes_dropped);
    }
  }
}

}  // namespace gpsemu
