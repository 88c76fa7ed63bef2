// One u-blox port (see session.hpp).
#include "emulator/ubx/session.hpp"

#include "emulator/ubx/layouts.hpp"

#include <algorithm>
#include <utility>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/output.hpp"
#include "emulator/ubx/solution_grid.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::ubx {

Session::Session(SessionSettings settings)
    : settings_(std::move(settings)), machine_(settings_.start, settings_.stored) {
  // What the stored layers changed at power-up reaches the emulator as a client's change would.
  const Settings& now = machine_.settings();
  const Settings& start = machine_.defaults();
  if (now.output_period() != start.output_period()) effects_.emplace_back(MeasurementPeriodChanged{now.output_period()});
  const auto port = static_cast<std::size_t>(machine_.port());
  if (now.ports[port].baud != start.ports[port].baud && now.ports[port].baud != 0) {
    effects_.emplace_back(BaudChanged{now.ports[port].baud});
  }
}

bool Session::period_change_pending() const {
  return std::any_of(effects_.begin(), effects_.end(),
                     [](const Effect& e) { return std::holds_alternative<MeasurementPeriodChanged>(e); });
}

Session::Client& Session::client(ClientId id) {
  if (clients_.size() >= max_clients && clients_.find(id) == clients_.end()) clients_.erase(clients_.begin());
  return clients_[id];
}

void Session::client_left(ClientId id) {
  clients_.erase(id);
  // A CFG-VALSET transaction begun and not applied goes with the client that left (counted).
  if (machine_.transaction_open()) machine_.discard_transaction();
}

void Session::client_wrote(std::string_view bytes, ClientId id) {
  Client& c = client(id);
  const FrameStats before = c.reader.stats();
  const std::vector<ClientMessage> messages = c.reader.feed(bytes);
  const FrameStats& after = c.reader.stats();
  reader_stats_.frames_ok += after.frames_ok - before.frames_ok;
  reader_stats_.bad_checksum += after.bad_checksum - before.bad_checksum;
  reader_stats_.too_long += after.too_long - before.too_long;
  reader_stats_.sentences_ok += after.sentences_ok - before.sentences_ok;
  reader_stats_.bad_sentences += after.bad_sentences - before.bad_sentences;
  reader_stats_.garbage_bytes += after.garbage_bytes - before.garbage_bytes;
  reader_stats_.rtcm_ok += after.rtcm_ok - before.rtcm_ok;
  reader_stats_.rtcm_bad_crc += after.rtcm_bad_crc - before.rtcm_bad_crc;
  for (const ClientMessage& message : messages) {
    if (const auto* rtcm = std::get_if<rtk::Rtcm3Frame>(&message)) {
      handle_rtcm(*rtcm, c);
    } else {
      handle(machine_.handle(message), c);
    }
  }
}

void Session::handle_rtcm(const rtk::Rtcm3Frame& frame, Client& c) {
  const Settings& s = machine_.settings();
  if ((s.ports[static_cast<std::size_t>(machine_.port())].in_proto_mask & proto_rtcm3) == 0 ||
      !model_info(machine_.model()).rtcm_input) {
    ++stats_.rtcm_ignored;  // RTCM3 input off on this port, or a model without it: neither used nor reported
    return;
  }
  rtk::Rtcm3Message message = rtk::decode_rtcm3(frame.payload);
  const bool ubx_out = (s.ports[static_cast<std::size_t>(machine_.port())].out_proto_mask & proto_ubx) != 0;
  if (ubx_out && s.rate(msg::rxm_rtcm, machine_.port()) != 0 && model_has_message(machine_.model(), msg::rxm_rtcm)) {
    // RXM-RTCM version 2: flags (crcFailed 0; msgUsed 2 used, 1 not used), subType, refStation, msgType.
    PayloadWriter<layout::rxm_rtcm> w;
    w.set<"version">(0x02);
    w.set<"flags">((message.valid ? 2u : 1u) << 1);
    w.set<"subType">(message.subtype.value_or(0));
    w.set<"refStation">(message.station_id.value_or(0));
    w.set<"msgType">(message.type);
    Answer answer;
    append_frame(answer.bytes, msg::rxm_rtcm, w.bytes());
    handle(std::move(answer), c);
  }
  if (rtcm_.size() >= max_pending_rtcm) {
    rtcm_.erase(rtcm_.begin());
    ++stats_.rtcm_not_taken;
  }
  rtcm_.push_back(std::move(message));
}

void Session::handle(Answer answer, Client& c) {
  if (c.reply.size() + answer.bytes.size() <= max_reply_bytes) {
    c.reply += answer.bytes;
  } else {
    ++stats_.answers_dropped;  // whole: the answer and its ACK together
    stats_.answer_bytes_dropped += answer.bytes.size();
  }
  for (Effect& effect : answer.effects) {
    if (const auto* poll = std::get_if<PollOnce>(&effect)) {
      // One answer a kind, as a u-blox answers a NAV poll with its next solution.
      if (std::find(polled_.begin(), polled_.end(), poll->id) == polled_.end()) {
        polled_.push_back(poll->id);
      } else {
        ++stats_.polls_merged;
      }
    } else if (std::holds_alternative<MeasurementPeriodChanged>(effect) || std::holds_alternative<BaudChanged>(effect) ||
               std::holds_alternative<ColdStart>(effect)) {
      // The newest of a kind wins: what the receiver applies at its next epoch is the last setting.
      const auto same = std::find_if(effects_.begin(), effects_.end(),
                                     [&](const Effect& e) { return e.index() == effect.index(); });
      if (same != effects_.end()) {
        effects_.erase(same);
        ++stats_.effects_superseded;
      }
      effects_.push_back(std::move(effect));
    }
    // Rates, sentences and protocols are in the settings append_solution() reads.
  }
}

void Session::hardware_reset() {
  constexpr std::uint16_t kColdStart = 0xFFFF;  // navBbrMask: every navigation data cleared
  constexpr std::uint8_t kHardwareReset = 0x00;  // resetMode: hardware reset (watchdog) immediately
  Answer answer = machine_.reset(kColdStart, kHardwareReset);
  std::erase_if(answer.effects, [](const Effect& e) { return std::holds_alternative<ColdStart>(e); });
  const auto waiting = std::find_if(effects_.begin(), effects_.end(),
                                    [](const Effect& e) { return std::holds_alternative<ColdStart>(e); });
  if (waiting != effects_.end()) {
    effects_.erase(waiting);
    ++stats_.effects_superseded;
  }
  Client nobody;  // a reset answers no client
  handle(std::move(answer), nobody);
}

bool Session::on_solution_grid(nmea::UtcTime t) const {
  if (machine_.settings().output_period() == settings_.start.measurement_period) return true;
  return solution_grid(machine_.settings(), machine_.model()).contains(t);
}

std::string Session::take_reply(ClientId id) {
  const auto it = clients_.find(id);
  return it == clients_.end() ? std::string{} : std::exchange(it->second.reply, std::string{});
}

std::vector<Effect> Session::take_effects() { return std::exchange(effects_, std::vector<Effect>{}); }

void Session::append_solution(const ReceiverEpoch& epoch, std::string& out) {
  const nmea::Fix& fix = epoch.fix;
  if (!on_solution_grid(fix.time_utc)) return;
  NavExtras extras;
  extras.since_start = epoch.status.since_start;
  extras.time_to_first_fix = epoch.status.time_to_first_fix;
  extras.model = machine_.model();
  extras.time = epoch.status.time;
  extras.clock = epoch.status.clock;
  extras.rf = epoch.rf;
  extras.relpos = epoch.relative_position.value_or(RelPosNed{});

  const Settings& s = machine_.settings();
  const Port port = machine_.port();
  nmea::FormatOptions format = settings_.format;
  format.sentences = due_sentences(s, port, solutions_);
  ubx::append_solution(out, s, port, solutions_, fix, extras, polled_);
  nmea::append_epoch(fix, format, out);
  ubx::append_end_of_epoch(out, s, port, solutions_, fix, polled_);
  polled_.clear();
  ++solutions_;
}

}  // namespace gpsemu::ubx
