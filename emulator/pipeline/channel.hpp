// One receiver channel: pose source -> receiver model -> one fix (nmea::Fix) -> its receiver
// protocol (protocol/receiver_protocol.hpp) publishes it into the epoch's bytes. The same channel
// serves the emulator loop (one receiver or a fleet), the library facade and the Python module.
// What clients write to the receiver's outputs comes back through client_wrote() to the protocol
// (plain NMEA ignores it); the channel knows no protocol, only that interface.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/faults/fault_timeline.hpp"
#include "emulator/heading/moving_base.hpp"
#include "emulator/model/epoch.hpp"
#include "emulator/model/geo.hpp"
#include "emulator/model/noise/noise_model.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/model/receiver_clock.hpp"
#include "emulator/model/time.hpp"
#include "emulator/protocol/receiver_protocol.hpp"
#include "emulator/rtk/rtk_state.hpp"
#include "emulator/sources/pose_source.hpp"
#include "nmea/fix.hpp"
#include "transport/input/rtcm_socket.hpp"
#include "transport/output.hpp"

namespace gpsemu {

class RtkReceiver;

/// What a channel is made from (pipeline/run_settings.hpp builds it from a Config).
struct ChannelSettings {
  Geodetic origin;
  ReceiverOptions receiver;  ///< derived: measured noise sigma, sky seed (receiver_config.hpp)
  noise::NoiseConfig noise;
  std::uint64_t seed = 1;
  nmea::FormatOptions format;
  /// The receiver's protocol (protocol/registry.hpp chooses it); null: the NMEA sentences of `format`.
  std::shared_ptr<const protocol::ProtocolSpec> protocol;
  /// The faults of this receiver (--scenario), applied to each fix before the encoders.
  faults::FaultPlan faults;
  /// The RTK state timeline (corrections from the u-blox port or `rtcm`; docs/rtk.md).
  rtk::RtkTimeline rtk;
  /// --rtcm: a base station's RTCM3 stream read each epoch.
  std::optional<transport::RtcmInputSpec> rtcm;
  /// Its part in a moving-base pair: antenna offset (moves the position with the truth's yaw);
  /// a moving base appends its RTCM3 to each epoch, a rover reads it from its clients.
  heading::MovingBaseOptions moving_base;
};

/// One receiver's counts (a fleet's summary has one line per receiver).
struct ReceiverStats {
  std::uint64_t epochs_emitted = 0;
  std::uint64_t epochs_without_fix = 0;
  std::uint64_t epochs_silent = 0;  ///< epochs a `silence` fault left unwritten
  std::uint64_t replies_withheld_bytes = 0;  ///< answers to the client a `silence` kept back (bytes)
  std::uint64_t epochs_garbled = 0;          ///< epochs a `garble` fault corrupted
  std::uint64_t units_flipped = 0;           ///< sentences and frames with a bit flipped (bad checksum)
  std::uint64_t units_truncated = 0;         ///< sentences and frames cut short
  std::uint64_t epochs_delayed = 0;          ///< epochs a `latency` fault held back
};

class Channel final : public transport::ClientInput {
 public:
  /// The receiver model starts at `first_epoch`, with the protocol of settings.protocol (or the
  /// NMEA sentences of settings.format).
  Channel(const ChannelSettings& settings, UtcNs first_epoch);
  ~Channel();
  Channel(const Channel&) = delete;
  Channel& operator=(const Channel&) = delete;

  /// The pose source step(t) samples; made after the channel, as it refers to frame().
  void set_source(std::unique_ptr<sources::PoseSource> source) { source_ = std::move(source); }
  [[nodiscard]] sources::PoseSource* source() const { return source_.get(); }
  /// A further protocol, published after the ones before it; it answers its clients, its effects
  /// and corrections are not taken (the receiver's own protocol's are).
  void add_protocol(std::unique_ptr<protocol::ReceiverProtocol> p) { protocols_.push_back(std::move(p)); }

  /// Epoch `t` from the channel's own source (serviced first): the epoch as every protocol
  /// encoded it; bytes() holds its bytes.
  ReceiverEpoch step(UtcNs t);
  /// Epoch `t` from `truth` (none: no fix).
  ReceiverEpoch step(UtcNs t, const std::optional<sources::Truth>& truth);
  /// The last epoch's bytes (every protocol's, in order; with a `latency` fault: those whose time
  /// to leave has come by the epoch).
  [[nodiscard]] const std::string& bytes() const { return bytes_; }
  /// The same, to cut to what a serial line carries (protocol_effects.hpp).
  [[nodiscard]] std::string& bytes() { return bytes_; }

  /// True from the first epoch its source has no truth for (sticky): nothing more is written.
  bool ended_at(UtcNs t) { return ended_ = ended_ || source_->ended_at(t); }
  [[nodiscard]] bool ended() const { return ended_; }

  void client_wrote(std::string_view bytes, ClientId client) override;
  /// Every protocol's answer to what `client` wrote, in order.
  [[nodiscard]] std::string take_reply(ClientId client) override;
  void client_left(ClientId client) override;
  /// Whether a protocol reads client input (a u-blox port); NMEA alone drops it.
  [[nodiscard]] bool reads_input() const override;

  /// The receiver's own protocol (settings.protocol): its effects and corrections are applied.
  [[nodiscard]] protocol::ReceiverProtocol& protocol() const { return *protocol_; }
  /// Cold start at `t` (a client asked: protocol::ColdStart): the receiver model starts again, no
  /// fix until it reacquires.
  void cold_start(UtcNs t);
  /// A reset fault at `t`: the receiver model starts again with a cold start of `cold_start_s`
  /// and the protocol is asked for a hardware cold reset (a u-blox: RAM from its layers, its rate
  /// and messages back to them; the period and baud effects follow at the next epoch).
  void reboot(UtcNs t, double cold_start_s);

  [[nodiscard]] const LocalFrame& frame() const { return frame_; }
  /// The antenna's true position at the last epoch (local frame), if the source had one.
  [[nodiscard]] const std::optional<Enu>& last_truth_m() const { return last_truth_m_; }
  [[nodiscard]] const Receiver& receiver() const { return *receiver_; }
  [[nodiscard]] const ChannelSettings& settings() const { return settings_; }
  /// The receiver's faults (--scenario, and live ones from the control socket).
  [[nodiscard]] const faults::FaultTimeline& faults() const { return *faults_; }
  [[nodiscard]] faults::FaultTimeline& faults() { return *faults_; }
  /// The RTK state and its correction inputs (rtk_receiver.hpp).
  [[nodiscard]] const RtkReceiver& rtk() const { return *rtk_; }
  [[nodiscard]] RtkReceiver& rtk() { return *rtk_; }
  /// A `latency` fault holds epochs back: the epoch time the first of them is due at, if any.
  [[nodiscard]] std::optional<UtcNs> delayed_until() const {
    return delayed_.empty() ? std::nullopt : std::optional<UtcNs>(delayed_.front().release);
  }
  /// The held-back bytes due by `t`, in order; valid until the next call.
  [[nodiscard]] std::string_view take_delayed(UtcNs t);
  [[nodiscard]] ReceiverStats& stats() { return stats_; }
  /// A rover's RTCM3 input (frames and bad CRCs seen in what its clients wrote).
  /// A rover's: the moving base's 4072.0 messages its clients forwarded (frames with a bad CRC are
  /// counted by the protocol's input, with every other RTCM3 frame).
  [[nodiscard]] std::uint64_t moving_base_frames() const { return moving_base_frames_; }
  [[nodiscard]] const ReceiverStats& stats() const { return stats_; }

 private:
  ChannelSettings settings_;
  LocalFrame frame_;  ///< referenced by the receiver and the source: a Channel never moves
  std::unique_ptr<Receiver> receiver_;
  std::unique_ptr<sources::PoseSource> source_;
  std::vector<std::unique_ptr<protocol::ReceiverProtocol>> protocols_;
  protocol::ReceiverProtocol* protocol_ = nullptr;  ///< the receiver's own: protocols_'s first
  std::optional<faults::FaultTimeline> faults_;
  std::unique_ptr<RtkReceiver> rtk_;
  ReceiverStatusTracker status_;  ///< run time, TTFF, time validity, clock: the epoch's last stage
  /// Applies the byte-level faults (garble, latency) to the epoch `t`'s bytes.
  void apply_byte_faults(UtcNs t, const faults::EpochEffect& effect);

  struct Delayed {
    UtcNs release;  ///< the epoch time it is due at (its epoch + the latency)
    std::string bytes;
  };
  std::string bytes_;
  std::deque<Delayed> delayed_;  ///< `latency`: epochs held back, in order
  std::string released_;         ///< take_delayed()'s bytes
  bool ended_ = false;
  bool silent_ = false;  ///< the last epoch was silenced: answers are withheld too
  ReceiverStats stats_;
  std::optional<heading::RoverRelPos> rover_;  ///< a rover's NAV-RELPOSNED
  std::uint64_t moving_base_frames_ = 0;      ///< a rover's: 4072.0 frames forwarded by its clients
  std::optional<UtcNs> last_step_;             ///< the latest epoch stepped
  std::optional<Enu> last_truth_m_;            ///< its truth (the bench view's error against it)
  std::optional<UtcNs> last_corrections_;      ///< the epoch before which the base's RTCM3 last arrived
};

}  // namespace gpsemu
