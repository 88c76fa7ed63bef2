// One u-blox port as the emulator sees it, pure (PX4-GPSDrivers' shape; the UBX encoder of a
// receiver channel is a thin adapter over it): what the client writes goes in, the answers
// (ACKs, poll answers) come out at once through take_reply() for the loop to write before the
// next epoch, the effects the emulator must apply (measurement period, baud, cold start) through
// take_effects(), and each epoch's bytes (NAV and MON messages, NMEA sentences, then NAV-EOE, as
// the settings turn them on: output.hpp) through append_solution(). The receiver's own status
// (run time, TTFF, time validity, clock: model/receiver_clock.hpp) and RF state come with each
// epoch; a CFG-RST cold start is an effect the channel applies to the model.
//
// What waits for the next solution is bounded, as on a u-blox: a NAV poll waits once per message
// kind (a second poll of a kind already waiting gets the same one answer, counted), and of the
// effects (period, baud, cold start) the newest of each kind wins (the older ones are counted as
// superseded), so a client polling or reconfiguring a receiver whose next solution is hours away
// holds a few bytes, not a queue that grows with what it writes.
//
// The solutions lie on the start grid (the epochs the session is stepped at: --rate's) until the
// client asks for another period; then on the solution grid it asks for (solution_grid.hpp): an
// epoch off that grid writes nothing. The emulator loop steps the session on that grid itself
// (the MeasurementPeriodChanged effect); a caller stepping at a fixed rate gets it thinned.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/ubx/machine.hpp"
#include "emulator/ubx/nav.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::ubx {

struct SessionSettings {
  StartSettings start;           ///< model, port, start rate, NMEA sentences and UBX messages on
  nmea::FormatOptions format;    ///< how the NMEA part is written (its sentence set is ignored)
  std::uint64_t seed = 1;        ///< seed of the receiver clock (NAV-CLOCK): the run's --seed
  StoredLayers stored;           ///< BBR and flash at power-up (--receiver-state); RAM is built from them
};

/// One connection to the port (a TCP client, or whoever has the pty or serial line open): its own
/// frame reader and its own answers. 0 is the port's only connection.
using ClientId = std::uint64_t;

/// What the session folded or dropped (the summary reports it).
struct SessionStats {
  std::uint64_t polls_merged = 0;        ///< NAV polls of a kind already waiting: answered once
  std::uint64_t effects_superseded = 0;  ///< period, baud or cold-start effects a newer one replaced
  std::uint64_t answers_dropped = 0;     ///< answers (whole, with their ACK) past a client's reply limit
  std::uint64_t answer_bytes_dropped = 0;
  std::uint64_t rtcm_not_taken = 0;      ///< RTCM3 messages past max_pending_rtcm, dropped before anyone took them
  /// RTCM3 frames (good CRC) ignored: the port's input protocols (CFG-PRT inProtoMask bit 5,
  /// CFG-<port>INPROT-RTCM3X) exclude RTCM3, so the receiver does not use them.
  std::uint64_t rtcm_ignored = 0;
};

class Session {
 public:
  /// Answers waiting for one client at most (bytes): as a u-blox's TX buffer, what does not fit is
  /// dropped whole (one message's answer and its ACK together) and counted. 1000 CFG-RATE polls in
  /// one write (24 000 bytes of answers) fit.
  static constexpr std::size_t max_reply_bytes = 64 * 1024;
  /// Connections with a reader of their own at most; a further one takes the oldest's.
  static constexpr std::size_t max_clients = 64;

  explicit Session(SessionSettings settings);

  /// Bytes `client` wrote (any chunking): read by that client's own frame reader, answered to it.
  void client_wrote(std::string_view bytes, ClientId client = 0);
  /// The answers to `client` not yet written (empties them).
  [[nodiscard]] std::string take_reply(ClientId client = 0);
  /// `client` went away (disconnected, closed the device): its half-read frame and unwritten
  /// answers are dropped, so the next client starts clean.
  void client_left(ClientId client);
  /// MeasurementPeriodChanged, BaudChanged and ColdStart effects not yet taken (empties them).
  /// At power-up: the period and baud the stored layers give, when they differ from the start's.
  [[nodiscard]] std::vector<Effect> take_effects();
  /// RTCM3 messages the clients wrote (corrections), decoded, in order (empties them). RXM-RTCM
  /// reports each one to its client at once when the port's rate for it is on.
  [[nodiscard]] std::vector<rtk::Rtcm3Message> take_rtcm() { return std::exchange(rtcm_, {}); }
  /// RTCM3 messages kept for take_rtcm() at most; older ones are dropped (counted).
  static constexpr std::size_t max_pending_rtcm = 256;
  /// Whether a new solution period waits in take_effects() (the loop reschedules at once).
  [[nodiscard]] bool period_change_pending() const;

  /// A hardware reset with every navigation data cleared that no client asked for (a reset
  /// fault's reboot, whose receiver model the caller restarts itself): RAM reloaded from the
  /// layers, the receiver's own state (msss, TTFF, time validity) starts again, the period and
  /// baud changes wait in take_effects() as a client's CFG-RST leaves them; no ColdStart effect
  /// (a client's one still waiting is superseded).
  void hardware_reset();

  /// Appends the bytes of `epoch` (its fix, front end and relative position) to `out`: nothing
  /// off the measurement grid.
  void append_solution(const ReceiverEpoch& epoch, std::string& out);

  /// Whether a solution falls at `t`: any epoch while the period is the start one, else those on
  /// the asked solution grid.
  [[nodiscard]] bool on_solution_grid(nmea::UtcTime t) const;

  [[nodiscard]] const ConfigMachine& machine() const { return machine_; }
  /// Every client's frame readers' counts, added up.
  [[nodiscard]] const FrameStats& reader_stats() const { return reader_stats_; }
  [[nodiscard]] const SessionStats& stats() const { return stats_; }
  [[nodiscard]] std::uint64_t solutions() const { return solutions_; }
  /// NAV polls and effects waiting for the next solution (at most one a kind of each).
  [[nodiscard]] std::size_t polls_waiting() const { return polled_.size(); }
  [[nodiscard]] std::size_t effects_waiting() const { return effects_.size(); }

 private:
  struct Client {
    FrameReader reader;
    std::string reply;
  };
  Client& client(ClientId id);
  /// Keeps `answer` for client `c` (or drops it whole past max_reply_bytes), collects its effects.
  void handle(Answer answer, Client& c);
  /// Keeps an RTCM3 frame for take_rtcm() and answers RXM-RTCM when it is on.
  void handle_rtcm(const rtk::Rtcm3Frame& frame, Client& c);

  SessionSettings settings_;
  ConfigMachine machine_;
  std::map<ClientId, Client> clients_;
  FrameStats reader_stats_;
  SessionStats stats_;
  std::vector<Effect> effects_;
  std::vector<MessageId> polled_;  ///< one a kind
  std::vector<rtk::Rtcm3Message> rtcm_;  ///< at most max_pending_rtcm
  std::uint64_t solutions_ = 0;
};

}  // namespace gpsemu::ubx
