// A u-blox's transmit buffer on a serial line that cannot carry an epoch: the receiver queues each
// message of the epoch (NMEA sentences, then UBX frames) while the line has room for it in the
// epoch's time (baud / 10 bytes a second, 8N1), and drops a message that does not fit whole (the
// TX buffer overflows). Never half a sentence or frame: what goes out still parses. Pure.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

namespace gpsemu::ubx {

/// Bytes a line at `baud` (8N1: 10 bits a byte) carries in `period`.
[[nodiscard]] std::size_t line_bytes_per_period(std::uint32_t baud, std::chrono::nanoseconds period);

struct TxDrops {
  std::uint64_t messages = 0;  ///< messages dropped
  std::uint64_t bytes = 0;     ///< their bytes
};

/// Keeps, in order, each whole message of `epoch` (a `$...\r\n` sentence or a 0xB5 0x62 frame)
/// that still fits in `budget_bytes`, drops the others; returns what was dropped. Bytes that are
/// neither (never written by the encoder) count as one message.
TxDrops fit_epoch_to_line(std::string& epoch, std::size_t budget_bytes);

}  // namespace gpsemu::ubx
