// The u-blox encoder of a receiver channel: a thin adapter over ubx::Session (emulator/ubx/,
// pure). Each epoch it writes what the receiver's u-blox settings turn on (UBX NAV messages, NMEA
// sentences, then NAV-EOE, on the client's measurement grid); what a client writes is answered at once
// through take_reply(), which the output writes back before the next epoch. Bad frames from the
// client are counted (ubx::FrameStats) and logged at most once a second. The effects the emulator
// must apply (measurement period, baud, cold start) wait in take_effects().
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "emulator/pipeline/encoder.hpp"
#include "emulator/ubx/session.hpp"

namespace gpsemu {

class UbxEncoder final : public Encoder {
 public:
  explicit UbxEncoder(ubx::SessionSettings settings) : session_(std::move(settings)) {}

  void encode(const nmea::Fix& fix, std::string& out) override { session_.append_solution(fix, out); }
  void client_wrote(std::string_view bytes) override;
  [[nodiscard]] std::string take_reply() override { return session_.take_reply(); }

  /// Measurement period, baud and cold-start changes the client asked for, not yet taken.
  [[nodiscard]] std::vector<ubx::Effect> take_effects() { return session_.take_effects(); }
  [[nodiscard]] const ubx::Session& session() const { return session_; }
  /// The RF front end MON-HW and MON-RF report (a jam fault changes it).
  [[nodiscard]] ubx::RfState& rf() { return session_.rf(); }

 private:
  ubx::Session session_;
  std::uint64_t bad_frames_reported_ = 0;
  std::chrono::steady_clock::time_point last_report_{};
};

}  // namespace gpsemu
