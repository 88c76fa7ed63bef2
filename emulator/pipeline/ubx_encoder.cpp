#include "emulator/pipeline/ubx_encoder.hpp"

#include <spdlog/spdlog.h>

#include "emulator/pipeline/receiver_state.hpp"

namespace gpsemu {

void UbxEncoder::save_state() {
  const ubx::ConfigMachine& machine = session_.machine();
  if (!state_file_ || machine.stored_version() == saved_version_) return;
  saved_version_ = machine.stored_version();
  std::string error;
  if (write_receiver_state(*state_file_, machine.stored(), machine.model(), error)) {
    if (state_error_reported_) spdlog::info("u-blox: --receiver-state {} written again", *state_file_);
    state_error_reported_ = false;
  } else if (!state_error_reported_) {  // once until a write succeeds again
    spdlog::warn("u-blox: --receiver-state: {}; the stored configuration is kept in memory only", error);
    state_error_reported_ = true;
  }
}

void UbxEncoder::client_wrote(std::string_view bytes, transport::ClientId client) {
  session_.client_wrote(bytes, client);
  save_state();
  report_dropped_answers();
  const ubx::FrameStats& stats = session_.reader_stats();
  const std::uint64_t bad = stats.bad_checksum + stats.too_long + stats.rtcm_bad_crc;
  if (bad == bad_frames_reported_ || !bad_frame_log_.admit(transport::LogLimit::Clock::now())) return;
  (void)bad_frame_log_.take_suppressed();  // the line counts the frames themselves
  spdlog::warn("u-blox: {} bad frame(s) from the client ({} UBX bad checksum, {} UBX too long, {} RTCM3 bad CRC in all)",
               bad - bad_frames_reported_, stats.bad_checksum, stats.too_long, stats.rtcm_bad_crc);
  bad_frames_reported_ = bad;
}

void UbxEncoder::report_dropped_answers() {
  const ubx::SessionStats& stats = session_.stats();
  if (stats.answers_dropped == answers_dropped_reported_) return;
  if (transport::log_limited(answer_drop_log_, spdlog::level::warn,
                             "u-blox: {} answer(s) dropped whole, more than {} bytes of answers waited for their client "
                             "({} in all)",
                             stats.answers_dropped - answers_dropped_reported_, ubx::Session::max_reply_bytes,
                             stats.answers_dropped)) {
    answers_dropped_reported_ = stats.answers_dropped;
  }
}

}  // namespace gpsemu
