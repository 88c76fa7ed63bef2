// The u-blox configuration state machine (see machine.hpp).
#include "emulator/ubx/machine.hpp"

#include <utility>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/cfg_legacy.hpp"
#include "emulator/ubx/output.hpp"
#include "emulator/ubx/pubx.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::uint8_t kClassNav = 0x01;
constexpr std::uint8_t kClassMon = 0x0A;
constexpr std::uint8_t kClassCfg = 0x06;
constexpr std::size_t kMaxKeys = 64;  // keys in one CFG-VALSET/VALGET
constexpr std::uint8_t kLayerRam = 0x01;
constexpr std::uint8_t kLayerDefault = 7;

bool is_key_value_message(MessageId id) {
  return id == msg::cfg_valset || id == msg::cfg_valget || id == msg::cfg_valdel;
}

/// Keys with the group or item wildcard (0xFF / 0xFFFF) of a VALGET: not supported here.
bool is_wildcard(std::uint32_t key) { return (key & 0xFFFF) == 0xFFFF || ((key >> 16) & 0xFF) == 0xFF; }

}  // namespace

ConfigMachine::ConfigMachine(const StartSettings& start) : start_(start), settings_(start_settings(start)) {}

Answer ConfigMachine::feed(std::string_view bytes) {
  Answer answer;
  for (const ClientMessage& message : reader_.feed(bytes)) {
    Answer one = handle(message);
    answer.bytes += one.bytes;
    for (Effect& e : one.effects) answer.effects.push_back(std::move(e));
  }
  return answer;
}

Answer ConfigMachine::handle(const ClientMessage& message) {
  Answer answer;
  if (const auto* frame = std::get_if<Frame>(&message)) {
    handle_frame(*frame, answer);
  } else {
    handle_sentence(std::get<nmea::Sentence>(message), answer);
  }
  return answer;
}

void ConfigMachine::ack(MessageId id, bool ok, Answer& answer) {
  const std::string payload{static_cast<char>(id.msg_class), static_cast<char>(id.msg_id)};
  append_frame(answer.bytes, ok ? msg::ack_ack : msg::ack_nak, payload);
  ++(ok ? stats_.acks : stats_.naks);
}

void ConfigMachine::handle_sentence(const nmea::Sentence& sentence, Answer& answer) {
  const Snapshot before = snapshot();
  if (const auto cmd40 = parse_pubx40(sentence)) {
    (void)apply_pubx40(settings_, *cmd40);
  } else if (const auto cmd41 = parse_pubx41(sentence)) {
    (void)apply_pubx41(settings_, *cmd41);
  } else {
    ++stats_.ignored;
  }
  diff(before, answer);
}

void ConfigMachine::handle_frame(const Frame& frame, Answer& answer) {
  const MessageId id = frame.id;
  if (id == msg::mon_ver) {
    if (frame.payload.empty()) {
      append_frame(answer.bytes, msg::mon_ver, mon_ver_payload(start_.model));
    } else {
      ++stats_.ignored;
    }
    return;
  }
  if (id.msg_class == kClassNav || id.msg_class == kClassMon) {
    // A poll of a message the model has is answered with the next solution; one it lacks is not.
    if (frame.payload.empty() && solution_encodes(id) && model_has_message(start_.model, id)) {
      answer.effects.emplace_back(PollOnce{id});
    } else {
      ++stats_.ignored;
    }
    return;
  }
  if (id.msg_class != kClassCfg) {
    ++stats_.ignored;
    return;
  }
  if (is_key_value_message(id) && !model_info(start_.model).key_value_config) {
    ack(id, false, answer);  // an M8 does not know the generation-9 interface
    return;
  }
  if (id == msg::cfg_rst) {  // never acknowledged: the receiver resets
    if (frame.payload.size() == 4 && get_u2(frame.payload, 0) == 0xFFFF) answer.effects.emplace_back(ColdStart{});
    return;
  }
  if (id == msg::cfg_valget) {
    answer_valget(frame, answer);
    return;
  }
  if (answer_cfg_poll(frame, answer)) {
    ack(id, true, answer);
    return;
  }
  const Snapshot before = snapshot();
  const bool ok = apply_cfg(frame);
  ack(id, ok, answer);
  if (ok) diff(before, answer);
}

bool ConfigMachine::answer_cfg_poll(const Frame& frame, Answer& answer) {
  const MessageId id = frame.id;
  const std::size_t size = frame.payload.size();
  if (id == msg::cfg_prt && size <= 1) {
    if (size == 1 && get_u1(frame.payload, 0) > static_cast<std::uint8_t>(Port::spi)) return false;  // NAKed as a write
    const Port port = size == 0 ? start_.port : static_cast<Port>(get_u1(frame.payload, 0));
    append_frame(answer.bytes, id, cfg_prt_payload(settings_, port));
  } else if (id == msg::cfg_msg && size == 2) {
    if (!model_has_message(start_.model, {get_u1(frame.payload, 0), get_u1(frame.payload, 1)})) return false;
    append_frame(answer.bytes, id, cfg_msg_payload(settings_, {get_u1(frame.payload, 0), get_u1(frame.payload, 1)}));
  } else if (id == msg::cfg_rate && size == 0) {
    append_frame(answer.bytes, id, cfg_rate_payload(settings_));
  } else if (id == msg::cfg_nav5 && size == 0) {
    append_frame(answer.bytes, id, settings_.nav5);
  } else if (id == msg::cfg_gnss && size == 0) {
    append_frame(answer.bytes, id, settings_.gnss);
  } else if (id == msg::cfg_sbas && size == 0) {
    append_frame(answer.bytes, id, settings_.sbas);
  } else {
    return false;
  }
  return true;
}

bool ConfigMachine::apply_cfg(const Frame& frame) {
  const MessageId id = frame.id;
  const std::string_view p = frame.payload;
  if (id == msg::cfg_prt) return apply_cfg_prt(settings_, p);
  if (id == msg::cfg_msg) {
    if (p.size() >= 2 && !model_has_message(start_.model, {get_u1(p, 0), get_u1(p, 1)})) return false;
    return apply_cfg_msg(settings_, p, start_.port);
  }
  if (id == msg::cfg_rate) return apply_cfg_rate(settings_, p);
  if (id == msg::cfg_nav5) return apply_cfg_nav5(settings_, p);
  if (id == msg::cfg_gnss) return apply_cfg_gnss(settings_, p);
  if (id == msg::cfg_sbas) return apply_cfg_sbas(settings_, p);
  if (id == msg::cfg_valset) return apply_valset(p);
  if (id == msg::cfg_valdel) return p.size() >= 4 && (p.size() - 4) % 4 == 0;  // BBR/flash only: RAM unchanged
  if (id == msg::cfg_cfg) {
    if (p.size() != 12 && p.size() != 13) return false;
    if (get_u4(p, 8) != 0) {  // loadMask: the defaults come back; the port keeps its settings
      Settings loaded = start_settings(start_);
      loaded.ports = settings_.ports;
      settings_ = std::move(loaded);
    }
    return true;
  }
  return !p.empty();  // another CFG write (TP5, PM2, ITFM...): accepted without an effect
}

bool ConfigMachine::apply_valset(std::string_view p) {
  if (p.size() < 4 || get_u1(p, 0) > 1) return false;
  Settings next = settings_;
  std::size_t keys = 0;
  for (std::size_t at = 4; at < p.size(); ++keys) {
    const std::uint32_t key = get_u4(p, at);
    const std::size_t bytes = key_value_bytes(key);
    if (keys == kMaxKeys || at + 4 > p.size() || bytes == 0 || at + 4 + bytes > p.size()) return false;
    if (!model_has_key(key)) return false;  // a message key the model does not have
    if (!set_key(next, key, get_le(p, at + 4, static_cast<int>(bytes)))) return false;
    at += 4 + bytes;
  }
  if ((get_u1(p, 1) & kLayerRam) != 0) settings_ = std::move(next);  // BBR/flash only: takes effect after a restart
  return true;
}

void ConfigMachine::answer_valget(const Frame& frame, Answer& answer) {
  const std::string_view p = frame.payload;
  const bool well_formed = p.size() >= 8 && (p.size() - 4) % 4 == 0 && (p.size() - 4) / 4 <= kMaxKeys && get_u1(p, 0) == 0;
  if (!well_formed) {
    ack(frame.id, false, answer);
    return;
  }
  const std::uint8_t layer = get_u1(p, 1);
  const Settings defaults = start_settings(start_);
  const Settings& source = layer == kLayerDefault ? defaults : settings_;
  std::string out;
  put_u1(out, 1);  // version: response
  put_u1(out, layer);
  put_u2(out, get_u2(p, 2));  // position
  for (std::size_t at = 4; at < p.size(); at += 4) {
    const std::uint32_t key = get_u4(p, at);
    const std::optional<std::uint64_t> value = is_wildcard(key) ? std::nullopt : get_key(source, key);
    if (!value || key_value_bytes(key) == 0 || !model_has_key(key)) {
      ack(frame.id, false, answer);
      return;
    }
    put_u4(out, key);
    put_le(out, *value, static_cast<int>(key_value_bytes(key)));
  }
  append_frame(answer.bytes, msg::cfg_valget, out);
  ack(frame.id, true, answer);
}

ConfigMachine::Snapshot ConfigMachine::snapshot() const {
  Snapshot s;
  s.period = settings_.output_period();
  s.port = settings_.ports[static_cast<std::size_t>(start_.port)];
  s.rates.reserve(settings_.rates.size());
  for (const auto& [id, rates] : settings_.rates) s.rates.emplace_back(id, rates[static_cast<std::size_t>(start_.port)]);
  return s;
}

bool ConfigMachine::model_has_key(std::uint32_t key) const {
  const std::optional<MessageId> id = msgout_message(key);
  return !id || model_has_message(start_.model, *id);
}

void ConfigMachine::diff(const Snapshot& before, Answer& answer) const {
  const Port port = start_.port;
  if (before.period != settings_.output_period()) {
    answer.effects.emplace_back(MeasurementPeriodChanged{settings_.output_period()});
  }
  const auto changed = [&](MessageId id, std::uint8_t old_rate, std::uint8_t new_rate) {
    if (old_rate == new_rate) return;
    if (const auto type = sentence_of(id)) {
      if ((old_rate != 0) != (new_rate != 0)) answer.effects.emplace_back(NmeaSentenceChanged{*type, new_rate != 0});
    } else {
      answer.effects.emplace_back(MessageRateChanged{id, new_rate});
    }
  };
  // Both lists are sorted by id: one merge, each id once.
  auto was = before.rates.begin();
  auto now = settings_.rates.begin();
  while (was != before.rates.end() || now != settings_.rates.end()) {
    if (now == settings_.rates.end() || (was != before.rates.end() && was->first < now->first)) {
      changed(was->first, was->second, 0);
      ++was;
    } else if (was == before.rates.end() || now->first < was->first) {
      changed(now->first, 0, now->second[static_cast<std::size_t>(port)]);
      ++now;
    } else {
      changed(now->first, was->second, now->second[static_cast<std::size_t>(port)]);
      ++was;
      ++now;
    }
  }
  const PortSettings& was_port = before.port;
  const PortSettings& now_port = settings_.ports[static_cast<std::size_t>(port)];
  if (was_port.out_proto_mask != now_port.out_proto_mask) {
    answer.effects.emplace_back(
        OutputProtocolsChanged{(now_port.out_proto_mask & proto_ubx) != 0, (now_port.out_proto_mask & proto_nmea) != 0});
  }
  if (was_port.baud != now_port.baud && now_port.baud != 0) answer.effects.emplace_back(BaudChanged{now_port.baud});
}

}  // namespace gpsemu::ubx
