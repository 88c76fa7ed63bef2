#include "transport/tee_output.hpp"

#include <fmt/format.h>

#include "transport/posix/wall_clock.hpp"

namespace gpsemu::transport {

TeeOutput::TeeOutput(const std::filesystem::path& path, bool flush_each_epoch, WallClock now)
    : path_(path.string()), file_(path, flush_each_epoch), now_(std::move(now)) {
  if (!now_) now_ = [] { return std::chrono::system_clock::time_point{posix::wall_clock_now()}; };
}

std::string TeeOutput::sent_line(std::chrono::system_clock::time_point time) {
  using namespace std::chrono;
  const auto us = floor<microseconds>(time);
  const auto day = floor<days>(us);
  const year_month_day ymd{day};
  const hh_mm_ss hms{us - day};
  return fmt::format("# sent {:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:06}Z\n", static_cast<int>(ymd.year()),
                     static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()), hms.hours().count(),
                     hms.minutes().count(), hms.seconds().count(), hms.subseconds().count());
}

void TeeOutput::note(std::string_view line) {
  notes_.append(line);
  notes_ += '\n';
}

void TeeOutput::flush() {
  if (!notes_.empty()) {
    (void)file_.write_epoch(notes_);
    notes_.clear();
  }
  file_.flush();
}

WriteStatus TeeOutput::write_bytes(std::string_view bytes, std::string& error_text) {
  buffer_ = notes_;
  notes_.clear();
  buffer_ += sent_line(now_());
  buffer_.append(bytes);
  // The comment starts a line: an epoch whose bytes do not end a line would swallow it.
  if (!bytes.empty() && bytes.back() != '\n' && bytes.back() != '\r') buffer_ += "\r\n";
  const WriteStatus status = file_.write_epoch(buffer_);
  if (status != WriteStatus::ok) error_text = "the file output refused the epoch (see its own message)";
  return status;
}

}  // namespace gpsemu::transport
