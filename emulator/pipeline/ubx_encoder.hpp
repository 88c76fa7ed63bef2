// The u-blox encoder of a receiver channel: a thin adapter over ubx::Session (emulator/ubx/,
// pure). Each epoch it writes what the receiver's u-blox settings turn on (UBX NAV messages, NMEA
// sentences, then NAV-EOE, on the client's measurement grid); what a client writes is answered at once
// through take_reply(), which the output writes back before the next epoch. Bad frames from the
// client are counted (ubx::FrameStats) and logged at most once a second. The effects the emulator
// must apply (measurement period, baud, cold start) wait in take_effects().
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/pipeline/encoder.hpp"
#include "emulator/ubx/session.hpp"
#include "transport/log_limit.hpp"

namespace gpsemu {

class UbxEncoder final : public Encoder {
 public:
  /// `state_file`: where the stored layers are written each time a client changes them.
  explicit UbxEncoder(ubx::SessionSettings settings, std::optional<std::string> state_file = std::nullopt)
      : session_(std::move(settings)), state_file_(std::move(state_file)),
        saved_version_(session_.machine().stored_version()) {}

  void encode(const nmea::Fix& fix, std::string& out) override { session_.append_solution(fix, out); }
  void client_wrote(std::string_view bytes, transport::ClientId client) override;
  [[nodiscard]] std::string take_reply(transport::ClientId client) override { return session_.take_reply(client); }
  void client_left(transport::ClientId client) override { session_.client_left(client); }
  [[nodiscard]] bool reads_client_input() const override { return true; }

  /// Measurement period, baud and cold-start changes the client asked for, not yet taken.
  [[nodiscard]] std::vector<ubx::Effect> take_effects() { return session_.take_effects(); }
  [[nodiscard]] const ubx::Session& session() const { return session_; }
  /// RTCM3 corrections the clients wrote, not yet taken (the channel's RTK state takes them).
  [[nodiscard]] std::vector<rtk::Rtcm3Message> take_rtcm() { return session_.take_rtcm(); }
  /// The RF front end MON-HW and MON-RF report (a jam fault changes it).
  [[nodiscard]] ubx::RfState& rf() { return session_.rf(); }
  /// NAV-RELPOSNED's values (a rover of a moving-base pair), set before each epoch.
  [[nodiscard]] ubx::RelPosNed& relative_position() { return session_.relative_position(); }

 private:
  /// Logs answers the session dropped (past its reply limit), at most once a second.
  void report_dropped_answers();

  ubx::Session session_;
  /// Writes the stored layers when they changed since the last write.
  void save_state();

  std::optional<std::string> state_file_;
  std::uint64_t saved_version_ = 0;
  bool state_error_reported_ = false;
  std::uint64_t bad_frames_reported_ = 0;
  transport::LogLimit bad_frame_log_{1};
  std::uint64_t answers_dropped_reported_ = 0;
  transport::LogLimit answer_drop_log_{1};  ///< "answer(s) dropped whole" lines: at most one a second
};

}  // namespace gpsemu
