// The configuration handshake of a u-blox as a pure state machine (PX4-GPSDrivers' shape: the
// protocol over bytes, the port does the I/O): what a client writes in, the bytes a u-blox
// answers and the effects the caller applies out. Polls (an empty payload) are answered with the
// current configuration and ACK-ACK; writes change the settings and are answered ACK-ACK, or
// ACK-NAK (nothing changes) when the receiver would refuse them. MON-VER answers with the model's
// version; an M8 NAKs the generation-9 CFG-VALSET/VALGET/VALDEL. CFG-RST and $PUBX get no answer.
// A message the model does not have (model_has_message) is NAKed in CFG-MSG and CFG-VALSET/VALGET
// and its poll gets no answer; a poll of a NAV or MON message it has is answered (PollOnce) with
// the next solution.
// The configuration lives in layers (config_layers.hpp: RAM, BBR, flash, defaults): CFG-VALSET
// (with transactions), CFG-VALDEL, CFG-VALGET, CFG-CFG and a reset act on them as on a receiver.
// No UBX answer leaves a port whose output protocols exclude UBX (counted). A message costs time
// in proportion to what it changes: only the rates of the messages it names are compared.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "emulator/ubx/config_layers.hpp"
#include "emulator/ubx/frame.hpp"
#include "emulator/ubx/settings.hpp"

namespace gpsemu::ubx {

/// The navigation solution period (measRate x navRate) changed.
struct MeasurementPeriodChanged {
  std::chrono::milliseconds period{};
};
/// A UBX message's rate on the client's port changed (0 off, n every n-th solution).
struct MessageRateChanged {
  MessageId id;
  std::uint8_t rate = 0;
};
/// An NMEA sentence was turned on or off on the client's port.
struct NmeaSentenceChanged {
  nmea::SentenceType type = nmea::SentenceType::gga;
  bool on = false;
};
/// Which protocols the client's port outputs changed.
struct OutputProtocolsChanged {
  bool ubx = false;
  bool nmea = false;
};
/// The client's port changes to `baud`: apply it after the answer's bytes have been written
/// (a u-blox sends the ACK at the old rate).
struct BaudChanged {
  std::uint32_t baud = 0;
};
/// CFG-RST with every navigation data cleared: the receiver starts cold.
struct ColdStart {};
/// A NAV message was polled: write it once with the next solution.
struct PollOnce {
  MessageId id;
};
using Effect = std::variant<MeasurementPeriodChanged, MessageRateChanged, NmeaSentenceChanged,
                            OutputProtocolsChanged, BaudChanged, ColdStart, PollOnce>;

/// What one client message (or a chunk of bytes) produced.
struct Answer {
  std::string bytes;            ///< UBX frames to write to the client, in order
  std::vector<Effect> effects;  ///< to apply in order, after `bytes` are written
};

struct MachineStats {
  std::uint64_t acks = 0;        ///< ACK-ACK sent
  std::uint64_t naks = 0;        ///< ACK-NAK sent
  std::uint64_t ignored = 0;     ///< messages without an answer (unknown polls, non-PUBX NMEA)
  std::uint64_t unsent_answers = 0;  ///< UBX answers not written: the port's output excludes UBX
  std::uint64_t resets = 0;      ///< CFG-RST that reloaded the configuration from the layers
  std::uint64_t transactions_discarded = 0;  ///< CFG-VALSET transactions begun and never applied
  /// What the last ACK-NAK refused, for the summary: "CFG-VALSET: CFG-MSGOUT-UBX_RXM_RTCM_UART1
  /// (0x20910269): a message ublox-m8n lacks", "CFG-RATE: a message ublox-m10 lacks", "CFG-RATE".
  std::string last_nak;
};

class ConfigMachine {
 public:
  /// RAM starts as `start`'s settings (the defaults), then `stored`'s flash, then its BBR.
  explicit ConfigMachine(const StartSettings& start, StoredLayers stored = {});

  /// Consumes a client's bytes (any chunking) and answers every message they complete.
  [[nodiscard]] Answer feed(std::string_view bytes);
  /// Answers one message.
  [[nodiscard]] Answer handle(const ClientMessage& message);

  [[nodiscard]] const Settings& settings() const { return settings_; }
  /// The default layer: the emulator's start settings.
  [[nodiscard]] const Settings& defaults() const { return defaults_; }
  [[nodiscard]] const StoredLayers& stored() const { return stored_; }
  /// Changes each time BBR or flash changes (for saving them).
  [[nodiscard]] std::uint64_t stored_version() const { return stored_version_; }
  /// Whether a CFG-VALSET transaction is open (begun, not yet applied).
  [[nodiscard]] bool transaction_open() const { return transaction_.has_value(); }
  /// Forgets an open transaction (the client went away): counted as discarded.
  void discard_transaction();
  [[nodiscard]] ReceiverModel model() const { return start_.model; }
  [[nodiscard]] Port port() const { return start_.port; }
  [[nodiscard]] const FrameStats& reader_stats() const { return reader_.stats(); }
  [[nodiscard]] const MachineStats& stats() const { return stats_; }
  /// A reset no client asked for (a reset fault's reboot), as CFG-RST with `nav_bbr_mask` and
  /// `reset_mode` would do it: RAM reloaded from the layers (counted in stats().resets), the
  /// changes and a ColdStart (mask 0xFFFF) as effects.
  [[nodiscard]] Answer reset(std::uint16_t nav_bbr_mask, std::uint8_t reset_mode);

 private:
  void handle_frame(const Frame& frame, Answer& answer);
  void handle_sentence(const nmea::Sentence& sentence, Answer& answer);
  /// Answers a CFG poll (empty or selector payload); false when `frame` is no poll.
  bool answer_cfg_poll(const Frame& frame, Answer& answer);
  /// What a change is compared against: the period, the client port, the rates of the messages
  /// the message names (or every setting, for a load or a reset).
  struct Before {
    std::chrono::milliseconds period{};
    PortSettings port;
    std::vector<std::pair<MessageId, std::uint8_t>> rates;
    std::optional<Settings> all;
  };
  [[nodiscard]] Before before(std::vector<MessageId> touched, bool everything = false) const;
  /// Applies a CFG write; false: NAK.
  bool apply_cfg(const Frame& frame, Before& before);
  void answer_valget(const Frame& frame, Answer& answer);
  [[nodiscard]] bool apply_valset(std::string_view payload, Before& before);
  [[nodiscard]] bool apply_valdel(std::string_view payload);
  [[nodiscard]] bool apply_cfg_cfg(std::string_view payload, Before& before);
  void reset(std::string_view payload, Answer& answer);
  void reset(std::uint16_t nav_bbr_mask, std::uint8_t reset_mode, Answer& answer);
  /// Writes `keys` (validated) to the layers of `layer_bits`.
  void write_keys(const std::vector<std::pair<std::uint32_t, std::uint64_t>>& keys, std::uint8_t layer_bits,
                  Before& before);
  /// A UBX answer, unless the client's port does not output UBX.
  void reply(Answer& answer, MessageId id, std::string_view payload);
  void ack(MessageId id, bool ok, Answer& answer);
  /// False for a CFG-MSGOUT key of a message the model does not have, or a key of a group its firmware
  /// lacks (model_has_key_group()).
  [[nodiscard]] bool model_has_key(std::uint32_t key) const;
  /// Appends the effects of the change from `before` to the current settings.
  void diff(const Before& before, Answer& answer) const;
  [[nodiscard]] bool ubx_out() const;

  struct Transaction {
    std::uint8_t layers = 0;
    std::vector<std::pair<std::uint32_t, std::uint64_t>> keys;  ///< at most the catalogue's keys
  };

  StartSettings start_;
  Settings defaults_;
  StoredLayers stored_;
  Settings settings_;
  std::optional<Transaction> transaction_;
  std::uint64_t stored_version_ = 0;
  FrameReader reader_;
  MachineStats stats_;
  std::string nak_reason_;  ///< why the NAK being prepared refuses (" : ..."), empty when unknown
};

}  // namespace gpsemu::ubx
