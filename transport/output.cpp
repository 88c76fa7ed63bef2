#include "transport/output.hpp"

#include <spdlog/spdlog.h>

namespace gpsemu::transport {

WriteStatus Output::write_epoch(std::string_view bytes) {
  std::string error_text;
  const WriteStatus status = write_bytes(bytes, error_text);
  switch (status) {
    case WriteStatus::ok:
      ++stats_.epochs_written;
      stats_.bytes_written += bytes.size();
      return status;
    case WriteStatus::dropped:
      ++stats_.epochs_dropped;
      break;
    case WriteStatus::error:
      ++stats_.epochs_failed;
      break;
  }
  // Repeated failures are reported at most once a second, with how many were folded in.
  ++unreported_;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_report_ >= std::chrono::seconds(1)) {
    spdlog::warn("{}: epoch {} ({}){}", describe(),
                 status == WriteStatus::dropped ? "dropped" : "not written", error_text,
                 unreported_ > 1 ? fmt::format(" [{} since last report]", unreported_) : "");
    last_report_ = now;
    unreported_ = 0;
  }
  return status;
}

}  // namespace gpsemu::transport
