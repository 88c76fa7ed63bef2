// The u-blox port behind the receiver protocol interface (receiver_protocol.hpp): a thin adapter
// over ubx::Session (emulator/ubx/, pure). Each epoch it writes what the receiver's u-blox
// settings turn on (UBX NAV messages, NMEA sentences, then NAV-EOE, on the client's solution
// grid); what a client writes is answered at once through take_reply(). The session's effects
// become the interface's: CFG-RATE a solution grid (aligned to the week, at most the model's
// fastest rate: ubx/solution_grid.hpp), CFG-PRT a baud, CFG-RST a cold start; RTCM3 the client
// interleaves with UBX comes out as corrections; a reset fault is a hardware CFG-RST's reload
// (ubx::Session::hardware_reset()), asked for, not forged as a frame. Bad frames from the client
// and answers dropped are logged at most once a second; the stored layers are written to
// --receiver-state (state_file.hpp) each time a client changes them.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/common/log_limit.hpp"
#include "emulator/protocol/receiver_protocol.hpp"
#include "emulator/protocol/ublox/state_file.hpp"
#include "emulator/ubx/session.hpp"

namespace gpsemu::protocol {

class UbloxProtocol final : public ReceiverProtocol {
 public:
  /// `state_file`: where the stored layers are written each time a client changes them.
  explicit UbloxProtocol(ubx::SessionSettings settings, std::optional<StateFile> state_file = std::nullopt);

  void encode(const ReceiverEpoch& epoch, std::string& out) override { session_.append_solution(epoch, out); }
  [[nodiscard]] std::size_t widest_epoch_bytes(const Geometry& sky) const override;
  [[nodiscard]] std::string name() const override { return "u-blox"; }
  [[nodiscard]] std::string written() const override { return nmea_on_at_start_ ? "NMEA+UBX" : "UBX"; }
  [[nodiscard]] std::string receiver_name() const override;

  void client_wrote(std::string_view bytes, ClientId client) override;
  [[nodiscard]] std::string take_reply(ClientId client) override { return session_.take_reply(client); }
  void client_left(ClientId client) override { session_.client_left(client); }
  [[nodiscard]] bool reads_client_input() const override { return true; }

  [[nodiscard]] std::vector<Effect> take_effects() override;
  [[nodiscard]] bool period_change_pending() const override { return session_.period_change_pending(); }
  [[nodiscard]] std::vector<rtk::Rtcm3Message> take_corrections() override { return session_.take_rtcm(); }
  [[nodiscard]] std::uint64_t corrections_bad_crc() const override { return session_.reader_stats().rtcm_bad_crc; }
  void reset(ResetKind kind) override;

  [[nodiscard]] bool has_tx_buffer() const override { return true; }
  LineDrops fit_to_line(std::string& epoch, std::size_t budget_bytes) override;


  [[nodiscard]] std::string client_input_summary(std::string_view extra) const override;
  [[nodiscard]] std::string configuration_summary() const override;
  [[nodiscard]] std::string configuration_json() const override;

  /// The port itself (the bench view shows its configuration; tests read it).
  [[nodiscard]] const ubx::Session& session() const { return session_; }

 private:
  /// Logs answers the session dropped (past its reply limit), at most once a second.
  void report_dropped_answers();
  /// Writes the stored layers when they changed since the last write.
  void save_state();

  ubx::Session session_;
  nmea::FormatOptions format_;                 ///< how its NMEA part is written
  std::chrono::milliseconds start_period_{};   ///< --rate's: asking for it again is the run's grid
  bool nmea_on_at_start_ = false;
  std::optional<StateFile> state_file_;
  std::uint64_t saved_version_ = 0;
  bool state_error_reported_ = false;
  std::uint64_t bad_frames_reported_ = 0;
  LogLimit bad_frame_log_{1};
  std::uint64_t answers_dropped_reported_ = 0;
  LogLimit answer_drop_log_{1};  ///< "answer(s) dropped whole" lines: at most one a second
};

/// The widest epoch of a u-blox port with `settings`: the NMEA sentences on for `port` (written as
/// `format` says, for the satellites of `sky`), then the UBX messages on.
[[nodiscard]] std::size_t widest_ublox_epoch_bytes(const nmea::FormatOptions& format, const ubx::Settings& settings,
                                                   ubx::Port port, ReceiverModel model, const Geometry& sky);

/// The u-blox port of `settings` (its stored layers written to `state_file`, when given).
[[nodiscard]] std::shared_ptr<const ProtocolSpec> ublox_protocol(ubx::SessionSettings settings,
                                                                 std::optional<StateFile> state_file = std::nullopt);

/// `protocol` as a u-blox port, or null.
[[nodiscard]] inline const UbloxProtocol* as_ublox(const ReceiverProtocol& protocol) {
  return dynamic_cast<const UbloxProtocol*>(&protocol);
}

}  // namespace gpsemu::protocol
