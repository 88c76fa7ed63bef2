// libFuzzer target for the per-sender assembly of --rtcm input (pipeline/rtk_receiver.hpp): a
// scripted RTCM socket hands the receiver what the input says, chunk by chunk:
//   byte 0 of a chunk: source (low 4 bits: 16 senders, more than the receiver keeps at once) and
//   whether the source's stream ends (0x80: a TCP connection closed); byte 1: length (0..255); then
//   that many bytes (the rest of the input when shorter). The receiver is serviced every few chunks.
// Checked: while no more senders than RtkReceiver::kMaxStreams were ever seen and no stream ended,
// the messages the receiver counts are exactly the frames each sender's bytes hold alone (a fresh
// Rtcm3Reader per sender over all its bytes): bytes of two senders never make or break a frame
// between them. Always: counts by type add up, the RTK state's quality is one of the four, drain()
// reads what is left, and a sender seen again after an eviction starts a fresh stream (no crash, no
// read past the bytes handed).
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "emulator/pipeline/rtk_receiver.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "tests/fuzz/fuzz_check.hpp"
#include "transport/input/rtcm_socket.hpp"

namespace {

using namespace gpsemu;

struct Chunk {
  std::uint64_t source = 0;
  std::string bytes;
  bool closed = false;
};

class ScriptedRtcmSocket final : public transport::RtcmSocket {
 public:
  explicit ScriptedRtcmSocket(std::deque<Chunk>* queue) : queue_(queue) {}
  std::optional<transport::RtcmBytes> receive() override {
    if (queue_->empty()) return std::nullopt;
    current_ = std::move(queue_->front());
    queue_->pop_front();
    return transport::RtcmBytes{current_.bytes, current_.source, current_.closed};
  }
  std::string describe() const override { return "scripted:0"; }
  void frame_from(std::uint64_t source) override { framed_.insert(source); }
  Drops drops() const override { return {}; }
  std::set<std::uint64_t> framed_;

 private:
  std::deque<Chunk>* queue_;
  Chunk current_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::deque<Chunk> queue;
  auto socket = std::make_unique<ScriptedRtcmSocket>(&queue);
  ScriptedRtcmSocket* scripted = socket.get();
  RtkReceiver receiver(rtk::RtkTimeline{}, std::move(socket));

  std::map<std::uint64_t, std::string> sent;  // every sender's bytes, in order
  bool simple = true;                          // no eviction, no stream ended
  std::size_t at = 0, chunks = 0;
  while (at + 2 <= size) {
    Chunk c;
    c.source = data[at] & 0x0F;
    c.closed = (data[at] & 0x80) != 0;
    const std::size_t n = std::min<std::size_t>(data[at + 1], size - at - 2);
    at += 2;
    if (!c.closed) {
      c.bytes.assign(reinterpret_cast<const char*>(data) + at, n);
      at += n;
      sent[c.source] += c.bytes;
    } else {
      simple = false;
    }
    queue.push_back(std::move(c));
    if (sent.size() > RtkReceiver::kMaxStreams) simple = false;
    if (++chunks % 3 == 0) (void)receiver.service();
  }
  receiver.drain();
  GPSEMU_FUZZ_CHECK(queue.empty());

  const RtkCounts& counts = receiver.counts();
  std::uint64_t by_type = 0;
  for (const std::uint64_t n : counts.by_type) by_type += n;
  GPSEMU_FUZZ_CHECK(by_type == counts.messages);
  GPSEMU_FUZZ_CHECK(counts.invalid <= counts.messages);
  if (simple) {
    std::uint64_t frames = 0;
    for (const auto& [source, bytes] : sent) {
      rtk::Rtcm3Reader alone;
      const std::size_t found = alone.feed(bytes).size();
      frames += found;
      // A sender's frames are credited to that sender alone.
      GPSEMU_FUZZ_CHECK((found > 0) == (scripted->framed_.count(source) > 0));
    }
    GPSEMU_FUZZ_CHECK(frames == counts.messages);
  }
  nmea::Fix fix;
  fix.quality = nmea::FixQuality::gps;
  receiver.apply(UtcNs{std::chrono::seconds(1'700'000'000)}, fix, std::nullopt, LocalFrame(Geodetic{43.0, -89.0, 260.0}));
  GPSEMU_FUZZ_CHECK(fix.quality == nmea::FixQuality::gps || fix.quality == nmea::FixQuality::dgps ||
                    fix.quality == nmea::FixQuality::rtk_float || fix.quality == nmea::FixQuality::rtk_fixed);
  return 0;
}
