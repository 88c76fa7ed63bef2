// `--tee FILE`: a copy of everything the emulator sends, each epoch preceded by a comment line
// with the time it was handed to the outputs, so a session can be replayed exactly
// (`gpsemu replay FILE` skips the comment lines and paces by the sentences' own times):
//
//   # sent 2024-05-01T12:00:00.050123Z
//   $GPRMC,120000.00,A,...*hh
//   $GPGGA,120000.00,...*hh
//
// A live fault applied at an epoch (the control socket) is recorded before that epoch's "# sent"
// line as "# fault +SECONDS EPOCH_TIME {JSON}" (faults/tee_events.hpp): `--scenario` takes the file
// back and applies the same events at the same epochs.
//
// The send time is CLOCK_REALTIME (UTC, microseconds) when write_epoch() is called; the runner
// and the replay add this output last, so it is stamped after the other outputs were written.
// Writes like a file output (file_output.hpp): each epoch at once in real time, buffered in
// large blocks with --fast. Its counts are the file output's: an epoch is written once the
// operating system took all of its bytes (its "# sent" line included, counted in the bytes), and
// an epoch whose write failed (ENOSPC, EIO, a pipe whose reader left) is counted as failed.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "transport/file_output.hpp"
#include "transport/output.hpp"

namespace gpsemu::transport {

class TeeOutput final : public Output {
 public:
  using WallClock = std::function<std::chrono::system_clock::time_point()>;

  /// Opens `path` like FileOutput (created when missing, truncated at commit()). `now` (tests) replaces the system clock. Throws
  /// std::runtime_error naming the path when it cannot be opened for writing.
  TeeOutput(const std::filesystem::path& path, bool flush_each_epoch, WallClock now = {});

  [[nodiscard]] std::string describe() const override { return "tee " + path_; }
  void flush() override;
  [[nodiscard]] const OutputStats& stats() const override { return file_.stats(); }
  [[nodiscard]] bool gone() const override { return file_.gone(); }
  /// Truncates the file (FileOutput::commit()): until then an existing file is left as it was.
  void commit() override { file_.commit(); }

  /// A comment line of the emulator's (a live fault applied: "# fault ..."), written before the
  /// next epoch's "# sent" line, or at flush() when no epoch follows. `line` without its '\n'.
  void note(std::string_view line) override;

  /// "# sent 2024-05-01T12:00:00.050123Z\n" for `time` (microseconds, truncated).
  [[nodiscard]] static std::string sent_line(std::chrono::system_clock::time_point time);

 protected:
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;

 private:
  std::string path_;
  FileOutput file_;
  WallClock now_;
  std::string buffer_;
  std::string notes_;  ///< note() lines not yet written
};

}  // namespace gpsemu::transport
