// Writes a receiver's bytes to a regular file (`file:PATH`) or to standard output (`stdout`),
// for batch generation (`--fast`: large buffer, written in big blocks) and for watching a run
// with `tail -f` (real time: every epoch is handed to the operating system as it is written).
// An epoch counts as written once the operating system took all of its bytes; bytes are counted as
// the operating system takes them. A pipe whose reader has gone (EPIPE) makes the output gone().
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/config/spec/output_spec.hpp"
#include "transport/output.hpp"

namespace gpsemu::transport {

class FileOutput final : public Output {
 public:
  /// Bytes kept before they are written out when not flushing each epoch (bytes).
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

  /// Opens `path` for writing as `mode` says, creating it when missing, but changes nothing it
  /// holds before commit() (or the first write): destroyed before that, it leaves an existing file
  /// as it was and removes a file it created. With `flush_each_epoch` every epoch is written out
  /// at once (real time); without it, bytes are buffered (batch generation). Throws
  /// std::runtime_error naming the path when it cannot be opened for writing, or exists with
  /// FileMode::create_new.
  FileOutput(const std::filesystem::path& path, bool flush_each_epoch, FileMode mode = FileMode::truncate);

  /// Writes to the process's standard output (file descriptor 1, not std::cout), which it leaves
  /// open. Throws std::runtime_error when standard output is closed.
  static std::unique_ptr<FileOutput> to_stdout(bool flush_each_epoch);

  /// Flushes what is buffered, then closes the file (never standard output); removes a file it
  /// created if it was never committed.
  ~FileOutput() override;

  /// Takes the file over: truncates it (FileMode::truncate, a regular file). Throws
  /// std::runtime_error naming the path when it cannot.
  void commit() override;

  /// "file out.nmea" or "stdout".
  [[nodiscard]] std::string describe() const override { return description_; }
  /// Writes out everything buffered, waiting (up to a few seconds) for a slow reader.
  void flush() override;
  [[nodiscard]] bool gone() const override { return gone_; }

 protected:
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override;

 private:
  enum class DrainResult { done, would_block, failed };

  FileOutput(int fd, bool owns_fd, std::string description, bool flush_each_epoch);
  DrainResult drain(bool wait, std::string& error_text);
  /// commit()'s work; false (with `error_text`) when the file cannot be truncated.
  bool take_over(std::string& error_text);
  /// The operating system took the first `bytes` of pending_: counts them and the epochs they complete.
  void sent(std::size_t bytes);

  int fd_ = -1;
  bool owns_fd_ = false;
  FileMode mode_ = FileMode::append;  ///< standard output: nothing to truncate
  bool committed_ = false;
  std::filesystem::path created_;  ///< the file this output created (removed if never committed)
  std::string description_;
  bool flush_each_epoch_ = false;
  std::string pending_;  ///< bytes accepted but not yet handed to the operating system
  /// Where each epoch in pending_ ends (offsets into pending_, ascending).
  std::vector<std::size_t> epoch_ends_;
  bool gone_ = false;    ///< EPIPE: the reader closed the pipe for good
};

}  // namespace gpsemu::transport
