// A receiver protocol as the receiver channel sees it: one interface, the shape of gpsd's driver
// descriptor (struct gps_type_t: a protocol is a set of hooks, the daemon's core calls them and
// never names a protocol). What a client writes comes in (client_wrote); out come each epoch's
// bytes for the one epoch value (encode), the answers to that client (take_reply), the effects the
// emulator applies to the running receiver (a solution period, a baud, a cold start:
// take_effects) and the corrections the client sent (RTCM3: take_corrections). The emulator asks
// the protocol for a reset (a reset fault) with reset(). Plain NMEA (nmea_protocol.hpp) and the
// u-blox port (ublox/ublox_protocol.hpp) implement it; registry.hpp says which a receiver has.
// A protocol state machine stays pure code over bytes (PX4-GPSDrivers' shape): the pipeline does
// the I/O and applies the effects (pipeline/protocol_effects.hpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "emulator/common/client_id.hpp"
#include "emulator/model/epoch.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/model/time.hpp"
#include "emulator/rtk/rtcm3_messages.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::protocol {

/// When a receiver computes solutions once its client chose a period: every `period`, at the
/// times next_after() gives (a u-blox aligns them to the week of its reference time).
struct SolutionGrid {
  std::chrono::nanoseconds period{};
  std::function<UtcNs(UtcNs)> next_after;  ///< the first solution time strictly after t
};

/// From the receiver's next epoch on, its solutions lie on `grid` (empty: the run's grid, --rate).
struct PeriodChanged {
  std::optional<SolutionGrid> grid;
  std::string warning;  ///< when the period asked for is not the one applied: why (logged as a warning)
};
/// The client's port changes speed: the receiver's serial outputs drain, then change.
struct BaudChanged {
  std::uint32_t baud_bps = 0;
};
/// The receiver model starts again (no fix until it reacquires).
struct ColdStart {};

/// What the emulator applies at the receiver's next epoch, after the answer is written.
struct Effect {
  std::string origin;  ///< what asked for it, for the log lines ("u-blox CFG-RATE")
  std::variant<PeriodChanged, BaudChanged, ColdStart> what;
};

/// A reset the emulator asks a protocol for (a reset fault).
enum class ResetKind {
  hardware_cold,  ///< a hardware reset with every navigation data cleared (u-blox: CFG-RST 0xFFFF, mode 0)
};

/// Messages (and their bytes) a transmit buffer dropped because the line could not carry them.
struct LineDrops {
  std::uint64_t messages = 0;
  std::uint64_t bytes = 0;
};

class ReceiverProtocol {
 public:
  virtual ~ReceiverProtocol() = default;

  // What the receiver writes.
  /// Appends this protocol's bytes for `epoch` to `out` (which holds the earlier protocols'
  /// bytes). The epoch is read-only: it is whole before any protocol sees it (model/epoch.hpp).
  virtual void encode(const ReceiverEpoch& epoch, std::string& out) = 0;
  /// The widest epoch it may write with its settings now, for satellites as `sky` (the model's
  /// worst case by system): the line budget's figure (bytes).
  [[nodiscard]] virtual std::size_t widest_epoch_bytes(const Geometry& sky) const = 0;
  /// Its name in log lines ("NMEA", "u-blox").
  [[nodiscard]] virtual std::string name() const = 0;
  /// What it writes, for the start-up lines: "NMEA", "UBX", "NMEA+UBX".
  [[nodiscard]] virtual std::string written() const = 0;
  /// The receiver it emulates, for the start-up lines ("u-blox NEO-M8N"); empty: a plain NMEA source.
  [[nodiscard]] virtual std::string receiver_name() const { return {}; }

  // What the client writes, and the answers.
  /// Bytes `client` wrote to one of the receiver's outputs, in arrival order. Default: ignored.
  virtual void client_wrote(std::string_view /*bytes*/, ClientId /*client*/) {}
  /// The answer to what `client` wrote, due at once (written back to it by the output before the
  /// next epoch: PX4 waits 250 ms for an ACK). Default: none.
  [[nodiscard]] virtual std::string take_reply(ClientId /*client*/) { return {}; }
  /// `client` went away: its half-read input is forgotten. Default: nothing.
  virtual void client_left(ClientId /*client*/) {}
  /// Whether client_wrote() reads the bytes rather than ignoring them. Default: no.
  [[nodiscard]] virtual bool reads_client_input() const { return false; }

  // Effects and corrections out, requests in.
  /// The effects the client asked for, not yet taken (empties them), in order.
  [[nodiscard]] virtual std::vector<Effect> take_effects() { return {}; }
  /// Whether a PeriodChanged waits in take_effects() (the loop reschedules at once).
  [[nodiscard]] virtual bool period_change_pending() const { return false; }
  /// The RTCM3 corrections the clients wrote, decoded, not yet taken (empties them).
  [[nodiscard]] virtual std::vector<rtk::Rtcm3Message> take_corrections() { return {}; }
  /// RTCM3 frames with a bad CRC seen in what the clients wrote.
  [[nodiscard]] virtual std::uint64_t corrections_bad_crc() const { return 0; }
  /// The emulator resets the receiver (its receiver model restarts apart): the protocol's own
  /// state follows (a u-blox reloads RAM from its layers). Default: nothing.
  virtual void reset(ResetKind /*kind*/) {}

  // The serial line.
  /// Whether a serial line limits each epoch to the whole messages it carries in the period (a
  /// u-blox's TX buffer); then fit_to_line() cuts it. Default: no (an NMEA source writes it all).
  [[nodiscard]] virtual bool has_tx_buffer() const { return false; }
  /// Keeps, in order, the whole messages of `epoch` that fit in `budget_bytes`; returns the rest's count.
  virtual LineDrops fit_to_line(std::string& /*epoch*/, std::size_t /*budget_bytes*/) { return {}; }

  // The exit summary.
  /// One line of what the clients wrote and were answered (empty when the protocol reads no
  /// input); `extra` is appended to its counts (the channel's own, e.g. a rover's base frames).
  [[nodiscard]] virtual std::string client_input_summary(std::string_view /*extra*/) const { return {}; }
  /// One line of what the configuration did not carry out (empty when nothing to say).
  [[nodiscard]] virtual std::string configuration_summary() const { return {}; }

  // The bench view.
  /// What its clients configured, as a JSON object's text (u-blox: frames read, ACKs and NAKs, the
  /// solution rate, the port's baud, the messages on); empty: nothing a client configures.
  [[nodiscard]] virtual std::string configuration_json() const { return {}; }
};

/// What a channel's protocol is made from: a receiver's choice (registry.hpp).
class ProtocolSpec {
 public:
  virtual ~ProtocolSpec() = default;
  /// A protocol for one channel.
  [[nodiscard]] virtual std::unique_ptr<ReceiverProtocol> make() const = 0;
  /// Its widest epoch with its start settings (the line budget checked at start-up, bytes).
  [[nodiscard]] virtual std::size_t widest_epoch_bytes(const Geometry& sky) const = 0;
  /// Whether a client may move the receiver's solutions off the run's grid (a u-blox's CFG-RATE):
  /// then a time between the run's epochs may still see one. Default: no.
  [[nodiscard]] virtual bool client_may_change_period() const { return false; }
};

}  // namespace gpsemu::protocol
