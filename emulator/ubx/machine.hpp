// The configuration handshake of a u-blox as a pure state machine (PX4-GPSDrivers' shape: the
// protocol over bytes, the port does the I/O): what a client writes in, the bytes a u-blox
// answers and the effects the caller applies out. Polls (an empty payload) are answered with the
// current configuration and ACK-ACK; writes change the settings and are answered ACK-ACK, or
// ACK-NAK (nothing changes) when the receiver would refuse them. MON-VER answers with the model's
// version; an M8 NAKs the generation-9 CFG-VALSET/VALGET/VALDEL. CFG-RST and $PUBX get no answer.
// A message the model does not have (model_has_message) is NAKed in CFG-MSG and CFG-VALSET/VALGET
// and its poll gets no answer; a poll of a NAV or MON message it has is answered (PollOnce) with
// the next solution.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

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
};

class ConfigMachine {
 public:
  explicit ConfigMachine(const StartSettings& start);

  /// Consumes a client's bytes (any chunking) and answers every message they complete.
  [[nodiscard]] Answer feed(std::string_view bytes);
  /// Answers one message.
  [[nodiscard]] Answer handle(const ClientMessage& message);

  [[nodiscard]] const Settings& settings() const { return settings_; }
  [[nodiscard]] ReceiverModel model() const { return start_.model; }
  [[nodiscard]] Port port() const { return start_.port; }
  [[nodiscard]] const FrameStats& reader_stats() const { return reader_.stats(); }
  [[nodiscard]] const MachineStats& stats() const { return stats_; }

 private:
  void handle_frame(const Frame& frame, Answer& answer);
  void handle_sentence(const nmea::Sentence& sentence, Answer& answer);
  /// Answers a CFG poll (empty or selector payload); false when `frame` is no poll.
  bool answer_cfg_poll(const Frame& frame, Answer& answer);
  /// Applies a CFG write; false: NAK.
  bool apply_cfg(const Frame& frame);
  void answer_valget(const Frame& frame, Answer& answer);
  [[nodiscard]] bool apply_valset(std::string_view payload);
  void ack(MessageId id, bool ok, Answer& answer);
  /// What diff() compares: the period, the client port's settings and its message rates (not a
  /// copy of the whole settings a write: a burst of CFG writes stays cheap).
  struct Snapshot {
    std::chrono::milliseconds period{};
    PortSettings port;
    std::vector<std::pair<MessageId, std::uint8_t>> rates;  ///< by id, every listed message's rate
  };
  [[nodiscard]] Snapshot snapshot() const;
  /// False for a CFG-MSGOUT key of a message the model does not have.
  [[nodiscard]] bool model_has_key(std::uint32_t key) const;
  /// Appends the effects of the change from `before` to the current settings.
  void diff(const Snapshot& before, Answer& answer) const;

  StartSettings start_;
  Settings settings_;
  FrameReader reader_;
  MachineStats stats_;
};

}  // namespace gpsemu::ubx
