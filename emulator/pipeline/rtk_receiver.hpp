// The RTK part of a receiver channel (docs/rtk.md): RTCM3 corrections come in from the receiver's
// protocol (a u-blox port splits them from its own frames) or a base station's stream (--rtcm tcp:PORT|udp:PORT,
// read each epoch); the RTK state machine (rtk/rtk_state.hpp) turns them into the fix's quality.
// Applied to each fix after the receiver model and before the faults: the position error is
// rescaled by the ratio of the state's noise scale to the configured quality's (noise_scale), the
// accuracies likewise (never below the state's floor), GGA quality 2/5/4 with the age of the
// corrections and the base's station id, NAV-PVT diffSoln/carrSoln/lastCorrectionAge from them.
// A configured --fix-quality at least as good as the state is kept (a constant rtk-fixed stays
// rtk-fixed); faults apply after it, so a forced quality or an outage wins. What arrives is
// counted by message type and logged: the first of each type once, bad CRCs at most once a second.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/common/log_limit.hpp"
#include "emulator/model/enu.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/time.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "emulator/rtk/rtk_state.hpp"
#include "nmea/fix.hpp"
#include "transport/input/rtcm_socket.hpp"

namespace gpsemu {

/// What came in and what the state was (the summary's RTK line).
struct RtkCounts {
  std::array<std::uint64_t, 4096> by_type{};  ///< decoded messages by type (DF002), both inputs
  std::uint64_t messages = 0;
  std::uint64_t invalid = 0;          ///< shorter than their type requires: counted, not used
  std::uint64_t stream_bad_crc = 0;   ///< --rtcm frames dropped for their CRC
  std::uint64_t stream_garbage_bytes = 0;
  std::uint64_t epochs_dgps = 0, epochs_float = 0, epochs_fixed = 0;  ///< fixes the state lifted
};

class RtkReceiver {
 public:
  /// Opens the --rtcm socket when given (throws std::runtime_error naming it when it cannot).
  RtkReceiver(const rtk::RtkTimeline& timeline, const std::optional<transport::RtcmInputSpec>& rtcm);
  /// The same over a socket already made (a fuzz target's scripted one).
  RtkReceiver(const rtk::RtkTimeline& timeline, std::unique_ptr<transport::RtcmSocket> socket);
  /// Streams assembled at once (the oldest is forgotten beyond this).
  static constexpr std::size_t kMaxStreams = 8;
  RtkReceiver(const RtkReceiver&) = delete;
  RtkReceiver& operator=(const RtkReceiver&) = delete;

  /// A decoded message from the u-blox port.
  void received(const rtk::Rtcm3Message& message);
  /// Reads what the --rtcm socket has (a bounded number of reads); returns how many it made
  /// (0: nothing waiting).
  std::size_t service();
  /// Applies the state at `t` to `fix` (see above); `truth_m` in `frame`'s ENU metres.
  void apply(UtcNs t, nmea::Fix& fix, const std::optional<Enu>& truth_m, const LocalFrame& frame);
  /// A cold start: the corrections and the convergence are forgotten.
  void restart() {
    state_.reset();
    status_ = {};
  }
  /// The state of the last apply() (default before any correction) and the base position known.
  [[nodiscard]] const rtk::RtkStatus& status() const { return status_; }
  [[nodiscard]] const std::optional<rtk::BasePosition>& base() const { return state_.base(); }

  [[nodiscard]] const RtkCounts& counts() const { return counts_; }
  /// At the end of a run: what is already waiting in the input is read and counted (used or
  /// dropped), so the summary accounts for every datagram a base sent before the stop.
  void drain() {
    for (int round = 0; round < 64 && service() > 0; ++round) {
    }
  }
  /// "RTK: 120 RTCM3 messages (1005 x10, 1077 x60, ...), 2 bad CRC; epochs DGPS 3, float 9, fixed 88";
  /// empty when nothing arrived. `port_bad_crc`: the u-blox port's (its frame readers count them).
  [[nodiscard]] std::string summary(std::uint64_t port_bad_crc) const;
  /// "tcp:127.0.0.1:2101" of --rtcm, empty without.
  [[nodiscard]] std::string input() const { return socket_ ? socket_->describe() : std::string{}; }

 private:
  rtk::RtkState state_;
  rtk::RtkStatus status_;
  std::unique_ptr<transport::RtcmSocket> socket_;
  struct Stream {
    std::uint64_t source = 0;
    rtk::Rtcm3Reader reader;
  };
  std::vector<Stream> streams_;  ///< one reader per connection, at most a few
  RtkCounts counts_;
  std::optional<nmea::FixQuality> logged_;  ///< the last state logged
  std::uint64_t bad_crc_logged_ = 0;
  LogLimit bad_crc_log_{1};
  LogLimit drop_log_{1};
  transport::RtcmSocket::Drops drops_logged_{};
};

}  // namespace gpsemu
