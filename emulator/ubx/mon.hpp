// The receiver's RF monitoring messages from its RF state (the epoch's, emulator/model/epoch.hpp): MON-HW (60 bytes,
// u-blox 7 and later; deprecated but still answered in protocol 27+) and MON-RF (protocol 27+:
// one 24-byte block per RF path, two on the dual-band F9P) and MON-HW2 (28 bytes: the I/Q
// imbalance; ArduPilot turns it on). Layouts: u-blox's interface
// descriptions (M8 protocol 18, F9 HPG 1.32); PX4 reads noisePerMS, agcCnt, jamInd and the
// jamming state from them. Pure.
#pragma once

#include <string>

#include "emulator/ubx/model.hpp"
#include "emulator/model/epoch.hpp"
#include "emulator/model/receiver_models.hpp"

namespace gpsemu::ubx {

/// MON-HW, 60 bytes.
[[nodiscard]] std::string mon_hw(const RfState& rf);
/// MON-HW2, 28 bytes.
[[nodiscard]] std::string mon_hw2();
/// MON-RF, 4 + 24 per block (1 block, 2 with dual_band(model)).
[[nodiscard]] std::string mon_rf(const RfState& rf, ReceiverModel model);

}  // namespace gpsemu::ubx
