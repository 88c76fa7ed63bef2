// What goes out with each solution (see output.hpp).
#include "emulator/ubx/output.hpp"

#include <algorithm>

#include "emulator/ubx/layouts.hpp"
#include "emulator/ubx/model.hpp"

namespace gpsemu::ubx {
namespace {

bool due(std::uint8_t rate, std::uint64_t solution_index) { return rate != 0 && solution_index % rate == 0; }

bool outputs(const Settings& s, Port port, std::uint16_t protocol) {
  return (s.ports[static_cast<std::size_t>(port)].out_proto_mask & protocol) != 0;
}

}  // namespace

std::vector<MessageId> due_messages(const Settings& s, Port port, std::uint64_t solution_index) {
  std::vector<MessageId> ids;
  if (!outputs(s, port, proto_ubx)) return ids;
  for (const auto& [id, rates] : s.rates) {  // a std::map: class, then id order
    if (due(rates[static_cast<std::size_t>(port)], solution_index) && solution_encodes(id)) {
      ids.push_back(id);
    }
  }
  return ids;
}

nmea::SentenceSet due_sentences(const Settings& s, Port port, std::uint64_t solution_index) {
  nmea::SentenceSet set;
  if (!outputs(s, port, proto_nmea)) return set;
  for (const nmea::SentenceType type : nmea::all_sentence_types) {
    const auto id = nmea_message(type);
    if (id && due(s.rate(*id, port), solution_index)) set.insert(type);
  }
  return set;
}

std::size_t widest_solution_ubx_bytes(const Settings& s, Port port, ReceiverModel model) {
  nmea::Fix widest;
  widest.satellites_in_view = static_cast<int>(nmea::max_satellites);
  for (nmea::SatelliteInView& sat : widest.satellites) {
    sat.prn = 1;
    sat.snr_dbhz = 45;  // every satellite tracked: NAV-SIG lists its signals
  }
  NavExtras extras;
  extras.model = model;
  std::size_t bytes = 0;
  for (const MessageId id : due_messages(s, port, 0)) {
    bytes += frame_overhead_bytes + solution_payload(id, widest, extras)->size();
  }
  // RXM-RTCM (session.cpp): an 8-byte report for each RTCM3 message the port takes.
  constexpr std::size_t kRxmRtcmPayloadBytes = layout_bytes(layout::rxm_rtcm);
  if (outputs(s, port, proto_ubx) && (s.ports[static_cast<std::size_t>(port)].in_proto_mask & proto_rtcm3) != 0 &&
      s.rate(msg::rxm_rtcm, port) != 0 && model_has_message(model, msg::rxm_rtcm)) {
    bytes += rtcm_messages_per_solution_budget * (frame_overhead_bytes + kRxmRtcmPayloadBytes);
  }
  return bytes;
}

void append_solution(std::string& out, const Settings& s, Port port, std::uint64_t solution_index,
                     const nmea::Fix& fix, const NavExtras& extras, std::span<const MessageId> polled) {
  std::vector<MessageId> ids = due_messages(s, port, solution_index);
  for (const MessageId id : polled) {
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
  }
  for (const MessageId id : ids) {
    if (id == msg::nav_eoe) continue;  // append_end_of_epoch()
    if (const auto payload = solution_payload(id, fix, extras)) append_frame(out, id, *payload);
  }
}

void append_end_of_epoch(std::string& out, const Settings& s, Port port, std::uint64_t solution_index,
                         const nmea::Fix& fix, std::span<const MessageId> polled) {
  const std::vector<MessageId> due = due_messages(s, port, solution_index);
  const bool on = std::find(due.begin(), due.end(), msg::nav_eoe) != due.end() ||
                  std::find(polled.begin(), polled.end(), msg::nav_eoe) != polled.end();
  if (on) append_frame(out, msg::nav_eoe, nav_eoe(fix));
}

}  // namespace gpsemu::ubx
