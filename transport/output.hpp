// The one transport interface: where a receiver's bytes go (pty, file, stdout, serial, sockets).
// The base class counts and rate-limits error reports (spdlog's sink pattern); a backend
// implements write_bytes() and, when it has input to drain or clients to accept, service().
// What a client writes to the output (a receiver's command port: gpsd's probes, a UBX poll) is
// handed to the output's ClientInput, if one is attached (the receiver channel's encoders), and
// otherwise dropped.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emulator/common/client_id.hpp"
#include "emulator/common/log_limit.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::transport {

class SerialOutput;  // serial_output.hpp

/// What one service() call of an output reads from a client and hands to its ClientInput at
/// most: 64 KiB, and no read started after 2 ms. The rest waits in the kernel for the next turn
/// of the loop, which checks its timer between turns: a burst of 20 000 configuration frames
/// delays no epoch and no signal by more than about one budget.
inline constexpr posix::InputBudget client_input_budget{.bytes = 64 * 1024, .time = std::chrono::milliseconds(2)};

enum class WriteStatus {
  ok,       ///< the whole epoch was handed to the operating system (a buffering backend: kept for it)
  dropped,  ///< the epoch was not sent (no room, no client): nothing partial went out
  error,    ///< the backend failed; it stays usable and may recover (unless gone())
};

struct OutputStats {
  std::uint64_t epochs_written = 0;
  std::uint64_t epochs_dropped = 0;
  std::uint64_t epochs_failed = 0;
  std::uint64_t bytes_written = 0;       ///< epochs' bytes the operating system took
  std::uint64_t epochs_empty = 0;        ///< epochs with nothing to send (a u-blox with every message off)
  std::uint64_t replies_written = 0;     ///< batches of answers (to one read of a client's) written between epochs
  std::uint64_t reply_bytes_written = 0; ///< their bytes (apart from the epochs')
  std::uint64_t replies_dropped = 0;     ///< batches dropped whole: no room for them (counted, logged)
  std::uint64_t reply_bytes_dropped = 0;
};

/// One connection to an output (emulator/common/client_id.hpp).
using gpsemu::ClientId;
/// A ClientId no output gave before.
[[nodiscard]] ClientId new_client_id();

/// Where the bytes a client wrote to an output go (pipeline/channel.hpp: the receiver's encoders).
class ClientInput {
 public:
  virtual ~ClientInput() = default;
  /// Bytes `client` wrote, in arrival order (any framing: a protocol decoder reassembles each
  /// client's bytes on their own).
  virtual void client_wrote(std::string_view bytes, ClientId client) = 0;
  /// What the receiver answers `client` at once (a u-blox's ACKs and poll answers), taken after
  /// each client_wrote(); the output writes it back to that client before the next epoch, after
  /// what is already queued. Default: nothing.
  [[nodiscard]] virtual std::string take_reply(ClientId /*client*/) { return {}; }
  /// `client` went away (disconnected, the pty closed by everyone): forget its half-read input.
  virtual void client_left(ClientId /*client*/) {}
  /// Whether what clients write is read (a u-blox's session parses it) rather than dropped (a
  /// receiver that only writes NMEA). Default: read.
  [[nodiscard]] virtual bool reads_input() const { return true; }
};

class Output {
 public:
  virtual ~Output() = default;
  Output() = default;
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;

  /// Writes one epoch (all its sentences) in one go. Never blocks for long; counts the result (an
  /// empty epoch is not written, and counted as empty).
  WriteStatus write_epoch(std::string_view bytes);

  /// Non-blocking housekeeping between epochs: read client input (handed to the ClientInput, or
  /// dropped), accept clients.
  virtual void service() {}

  /// Writes what the ClientInput answered to the input service() read (a u-blox's ACKs), at once,
  /// each answer to the client that asked (write_reply()). Called right after service(), outside
  /// the backend's own loops over its clients.
  void answer_clients();
  /// Answers waiting for answer_clients() at most (bytes); a further answer is dropped whole and
  /// counted (replies_dropped).
  static constexpr std::size_t max_pending_reply_bytes = 64 * 1024;

  /// Attaches where client input goes (nullptr: dropped). Not owned; outlives the output's use.
  void set_client_input(ClientInput* input) { client_input_ = input; }

  /// Work that must precede the next write_epoch() but need not be on time (a pty discards the
  /// bytes no client read). Many receivers in one process call it for every output ahead of the
  /// deadline, so the writes at the deadline are short; otherwise write_epoch() does it itself.
  virtual void prepare_epoch() {}

  /// A file descriptor to poll for readability before calling service(), or -1.
  [[nodiscard]] virtual int poll_fd() const { return -1; }

  /// Where a client connects: "/dev/pts/3 (link /tmp/gpsemu)", "stdout", "file out.nmea".
  [[nodiscard]] virtual std::string describe() const = 0;
  /// What the exit summary adds about this output's clients ("; clients: 3 connected, ..."), if it has any.
  [[nodiscard]] virtual std::string clients_summary() const { return {}; }
  /// Clients connected now (a TCP server's connections, the descriptors open on a pty when its
  /// watch can tell); empty: not known, or not an output clients connect to.
  [[nodiscard]] virtual std::optional<std::uint64_t> clients_connected() const { return std::nullopt; }
  /// The serial line this output writes (its baud, its modem lines), or null: asked, not cast to.
  [[nodiscard]] virtual SerialOutput* serial_line() { return nullptr; }
  [[nodiscard]] virtual const SerialOutput* serial_line() const { return nullptr; }
  /// A line of commentary about the run (a live fault applied): a recording output (the tee)
  /// writes it as a comment line; every other output ignores it.
  virtual void note(std::string_view /*line*/) {}

  /// Flushes buffered bytes (files). Called at shutdown.
  virtual void flush() {}

  /// Called once every output, the tee and the PPS line of the run are open: the output may now
  /// change what it writes to (a file output truncates its file). An output destroyed before
  /// (start-up failed) leaves its destination as it found it. A backend that needs it also
  /// commits at its first write.
  virtual void commit() {}

  /// Its counts (a backend that writes through another output gives that one's: TeeOutput).
  [[nodiscard]] virtual const OutputStats& stats() const { return stats_; }

  /// True once the output can never take bytes again (the reader of a pipe closed it: EPIPE).
  [[nodiscard]] virtual bool gone() const { return false; }

 protected:
  /// Backend hook: send `bytes` entirely or not at all. `error_text` receives a reason on error
  /// or drop, which the base class logs at most once a second.
  virtual WriteStatus write_bytes(std::string_view bytes, std::string& error_text) = 0;

  /// Backend hook: hands what `client` wrote to the attached ClientInput and keeps its answer for
  /// answer_clients(). Returns false when the bytes are dropped (no ClientInput, or one that does
  /// not read input): the backend counts them as discarded.
  bool client_wrote(std::string_view bytes, ClientId client);
  /// Backend hook: `client` went away; the ClientInput forgets its half-read input.
  void client_left(ClientId client);
  /// Backend hook: writes `bytes` (whole answers) to `client` behind what is queued for it, or
  /// keeps them for later; `dropped`: not written nor kept (no room), nothing partial went out.
  /// Default: write_bytes() (an output with one client).
  virtual WriteStatus write_reply(ClientId client, std::string_view bytes, std::string& error_text);
  /// Counts an answer dropped whole (a backend that kept it and then could not send it).
  void count_reply_dropped(std::uint64_t bytes) {
    ++stats_.replies_dropped;
    stats_.reply_bytes_dropped += bytes;
  }

  /// A buffering backend calls this in its constructor: an `ok` epoch is not counted as written
  /// then; the backend counts what the operating system takes (count_sent) or what is lost.
  void count_when_sent() { count_when_sent_ = true; }
  /// A buffering backend: the operating system took `bytes`, completing `epochs` epochs.
  void count_sent(std::uint64_t epochs, std::uint64_t bytes) {
    stats_.epochs_written += epochs;
    stats_.bytes_written += bytes;
  }
  /// A buffering backend: `epochs` buffered epochs (a partial one included) were lost.
  void count_lost(std::uint64_t epochs, const std::string& error_text) {
    stats_.epochs_failed += epochs;
    report(WriteStatus::error, error_text, epochs);
  }

 private:
  /// Logs a dropped or failed epoch (`count` of them) at most once a second.
  void report(WriteStatus status, const std::string& error_text, std::uint64_t count);

  void report_reply_drops();

  ClientInput* client_input_ = nullptr;
  bool count_when_sent_ = false;
  /// The ClientInput's answers not yet written, per client (few: the clients that wrote since the
  /// last answer_clients()).
  std::vector<std::pair<ClientId, std::string>> replies_;
  std::size_t reply_bytes_ = 0;
  std::uint64_t reply_drops_reported_ = 0;
  LogLimit reply_drop_log_{1};  ///< "answers ... dropped whole" lines: at most one a second
  OutputStats stats_;
  LogLimit report_log_{1};  ///< dropped or failed epochs: at most one line a second
};

}  // namespace gpsemu::transport
