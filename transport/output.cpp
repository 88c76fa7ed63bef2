#include "transport/output.hpp"

#include <spdlog/spdlog.h>

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
  // Repeated failures are reported at most once a second, with how many were folded in.
  unreported_ += count;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_report_ >= std::chrono::seconds(1)) {
    spdlog::warn("{}: {} ({}){}", describe(),
                 count > 1 ? fmt::format("{} epochs not written", count)
                           : (status == WriteStatus::dropped ? "epoch dropped" : "epoch not written"),
                 error_text, unreported_ > count ? fmt::format(" [{} since last report]", unreported_) : "");
    last_report_ = now;
    unreported_ = 0;
  }
}

void Output::client_wrote(std::string_view bytes) {
  if (client_input_ == nullptr) return;
  client_input_->client_wrote(bytes);
  reply_ += client_input_->take_reply();
}

void Output::answer_clients() {
  if (reply_.empty()) return;
  std::string error_text;
  if (write_bytes(reply_, error_text) == WriteStatus::ok) {
    ++stats_.replies_written;
    stats_.reply_bytes_written += reply_.size();
  }
  reply_.clear();
}

}  // namespace gpsemu::transport
