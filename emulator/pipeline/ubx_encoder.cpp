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

void UbxEncoder::client_wrote(std::string_view bytes) {
  session_.client_wrote(bytes);
  save_state();
  const ubx::FrameStats& stats = session_.machine().reader_stats();
  const std::uint64_t bad = stats.bad_checksum + stats.too_long;
  if (bad == bad_frames_reported_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_report_ < std::chrono::seconds(1)) return;
  spdlog::warn("u-blox: {} bad UBX frame(s) from the client ({} bad checksum, {} too long in all)",
               bad - bad_frames_reported_, stats.bad_checksum, stats.too_long);
  bad_frames_reported_ = bad;
  last_report_ = now;
}

}  // namespace gpsemu
