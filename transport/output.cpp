#include "transport/output.hpp"

#include <spdlog/spdlog.h>

#include <atomic>

namespace gpsemu::transport {

WriteStatus Output::write_epoch(std::string_view bytes) {
  if (bytes.empty()) {
    ++stats_.epochs_empty;
    return WriteStatus::ok;
  }
  std::string error_text;
  const WriteStatus status = write_bytes(bytes, error_text);
  switch (status) {
    case WriteStatus::ok:
      if (!count_when_sent_) {
        ++stats_.epochs_written;
        stats_.bytes_written += bytes.size();
      }
      return status;
    case WriteStatus::dropped:
      ++stats_.epochs_dropped;
      break;
    case WriteStatus::error:
      ++stats_.epochs_failed;
      break;
  }
  report(status, error_text, 1);
  return status;
}

void Output::report(WriteStatus status, const std::string& error_text, std::uint64_t count) {
  // Repeated failures go through the shared limiter: a line a second, with how many were suppressed.
  log_limited(report_log_, spdlog::level::warn, "{}: {} ({})", describe(),
              count > 1 ? fmt::format("{} epochs not written", count)
                        : (status == WriteStatus::dropped ? "epoch dropped" : "epoch not written"),
              error_text);
}

ClientId new_client_id() {
  static std::atomic<ClientId> next{1};
  return next.fetch_add(1);
}

bool Output::client_wrote(std::string_view bytes, ClientId client) {
  if (client_input_ == nullptr) return false;
  client_input_->client_wrote(bytes, client);
  const bool read = client_input_->reads_input();
  std::string reply = client_input_->take_reply(client);
  if (reply.empty()) return read;
  if (reply_bytes_ + reply.size() > max_pending_reply_bytes) {
    count_reply_dropped(reply.size());  // whole: every answer of this read together
    report_reply_drops();
    return read;
  }
  reply_bytes_ += reply.size();
  if (!replies_.empty() && replies_.back().first == client) {
    replies_.back().second += reply;
  } else {
    replies_.emplace_back(client, std::move(reply));
  }
  return read;
}

void Output::client_left(ClientId client) {
  if (client_input_ != nullptr) client_input_->client_left(client);
}

WriteStatus Output::write_reply(ClientId /*client*/, std::string_view bytes, std::string& error_text) {
  return write_bytes(bytes, error_text);
}

void Output::answer_clients() {
  if (replies_.empty()) return;
  for (const auto& [client, reply] : replies_) {
    std::string error_text;
    if (write_reply(client, reply, error_text) == WriteStatus::ok) {
      ++stats_.replies_written;
      stats_.reply_bytes_written += reply.size();
    } else {
      count_reply_dropped(reply.size());
    }
  }
  replies_.clear();
  reply_bytes_ = 0;
  report_reply_drops();
}

void Output::report_reply_drops() {
  if (stats_.replies_dropped == reply_drops_reported_) return;
  if (log_limited(reply_drop_log_, spdlog::level::warn,
                  "{}: {} batch(es) of answers to clients dropped whole, no room for them ({} bytes in all so far)",
                  describe(), stats_.replies_dropped - reply_drops_reported_, stats_.reply_bytes_dropped)) {
    reply_drops_reported_ = stats_.replies_dropped;
  }
}

}  // namespace gpsemu::transport
