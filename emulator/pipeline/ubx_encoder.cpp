#include "emulator/pipeline/ubx_encoder.hpp"

#include <spdlog/spdlog.h>

namespace gpsemu {

void UbxEncoder::client_wrote(std::string_view bytes, transport::ClientId client) {
  session_.client_wrote(bytes, client);
  const ubx::FrameStats& stats = session_.reader_stats();
  const std::uint64_t bad = stats.bad_checksum + stats.too_long;
  if (bad == bad_frames_reported_ || !bad_frame_log_.admit(transport::LogLimit::Clock::now())) return;
  (void)bad_frame_log_.take_suppressed();  // the line counts the frames themselves
  spdlog::warn("u-blox: {} bad UBX frame(s) from the client ({} bad checksum, {} too long in all)",
               bad - bad_frames_reported_, stats.bad_checksum, stats.too_long);
  bad_frames_reported_ = bad;
}

}  // namespace gpsemu
