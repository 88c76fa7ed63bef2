// The u-blox configuration state machine (see machine.hpp).
#include "emulator/ubx/machine.hpp"

#include <algorithm>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "emulator/ubx/bytes.hpp"
#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/cfg_legacy.hpp"
#include "emulator/ubx/output.hpp"
#include "emulator/ubx/pubx.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::uint8_t kClassNav = 0x01;
constexpr std::uint8_t kClassMon = 0x0A;
constexpr std::uint8_t kClassCfg = 0x06;
constexpr std::size_t kMaxKeys = 64;  // keys in one CFG-VALSET/VALGET/VALDEL
constexpr std::uint8_t kStoredLayerBits = layer_bit_bbr | layer_bit_flash;

// CFG-VALSET transaction (byte 2 of version 1).
constexpr std::uint8_t kTransactionNone = 0, kTransactionBegin = 1, kTransactionContinue = 2, kTransactionApply = 3;

// CFG-RST resetMode: a hardware reset (watchdog) at once, a controlled software reset, a hardware
// reset after shutdown. The others (GNSS only, GNSS stop/start) keep RAM.
bool reloads_configuration(std::uint8_t reset_mode) { return reset_mode == 0x00 || reset_mode == 0x01 || reset_mode == 0x04; }

/// Keys with the group or item wildcard (0xFF / 0xFFFF) of a VALGET: not supported here.
bool is_wildcard(std::uint32_t key) { return (key & 0xFFFF) == 0xFFFF || ((key >> 16) & 0xFF) == 0xFF; }

/// The key/value pairs of a VALSET payload from byte 4, validated; nullopt when one is malformed,
/// unknown or out of range (the whole message is NAKed).
std::optional<std::vector<std::pair<std::uint32_t, std::uint64_t>>> valset_keys(std::string_view p) {
  std::vector<std::pair<std::uint32_t, std::uint64_t>> keys;
  for (std::size_t at = 4; at < p.size();) {
    if (keys.size() == kMaxKeys || at + 4 > p.size()) return std::nullopt;
    const std::uint32_t key = get_u4(p, at);
    const std::size_t bytes = key_value_bytes(key);
    if (bytes == 0 || at + 4 + bytes > p.size()) return std::nullopt;
    const std::uint64_t value = get_le(p, at + 4, static_cast<int>(bytes));
    if (!key_accepts(key, value)) return std::nullopt;
    keys.emplace_back(key, value);
    at += 4 + bytes;
  }
  return keys;
}

}  // namespace

ConfigMachine::ConfigMachine(const StartSettings& start, StoredLayers stored)
    : start_(start), defaults_(start_settings(start)), stored_(std::move(stored)), settings_(power_up(defaults_, stored_)) {}

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
  } else if (const auto* sentence = std::get_if<nmea::Sentence>(&message)) {
    handle_sentence(*sentence, answer);
  }  // RTCM3 corrections change no configuration (the session takes them)
  return answer;
}

void ConfigMachine::discard_transaction() {
  if (!transaction_) return;
  transaction_.reset();
  ++stats_.transactions_discarded;
}

bool ConfigMachine::ubx_out() const {
  return (settings_.ports[static_cast<std::size_t>(start_.port)].out_proto_mask & proto_ubx) != 0;
}

void ConfigMachine::reply(Answer& answer, MessageId id, std::string_view payload) {
  if (!ubx_out()) {
    ++stats_.unsent_answers;
    return;
  }
  append_frame(answer.bytes, id, payload);
}

void ConfigMachine::ack(MessageId id, bool ok, Answer& answer) {
  const std::string payload{static_cast<char>(id.msg_class), static_cast<char>(id.msg_id)};
  reply(answer, ok ? msg::ack_ack : msg::ack_nak, payload);
  ++(ok ? stats_.acks : stats_.naks);
  if (!ok) stats_.last_nak = message_name(id) + nak_reason_;
  nak_reason_.clear();
}

ConfigMachine::Before ConfigMachine::before(std::vector<MessageId> touched, bool everything) const {
  Before b;
  b.period = settings_.output_period();
  b.port = settings_.ports[static_cast<std::size_t>(start_.port)];
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  for (const MessageId id : touched) b.rates.emplace_back(id, settings_.rate(id, start_.port));
  if (everything) b.all = settings_;
  return b;
}

void ConfigMachine::handle_sentence(const nmea::Sentence& sentence, Answer& answer) {
  if (const auto cmd40 = parse_pubx40(sentence)) {
    const auto id = nmea_message_from_name(cmd40->message);
    Before b = before(id ? std::vector<MessageId>{*id} : std::vector<MessageId>{});
    (void)apply_pubx40(settings_, *cmd40);
    diff(b, answer);
  } else if (const auto cmd41 = parse_pubx41(sentence)) {
    const Before b = before({});
    (void)apply_pubx41(settings_, *cmd41);
    diff(b, answer);
  } else {
    ++stats_.ignored;
  }
}

void ConfigMachine::handle_frame(const Frame& frame, Answer& answer) {
  const MessageId id = frame.id;
  if (id == msg::mon_ver) {
    if (frame.payload.empty()) {
      reply(answer, msg::mon_ver, mon_ver_payload(start_.model));
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
  // A configuration message the model lacks is NAKed: CFG-VAL* on an M8, the legacy CFG-*
  // messages on an M10 (its interface is CFG-VALSET/VALGET/VALDEL, CFG-CFG and CFG-RST).
  if (!model_has_message(start_.model, id) || (find_message(id) == nullptr && !model_info(start_.model).legacy_config)) {
    nak_reason_ = fmt::format(": a message {} lacks", model_info(start_.model).name);
    ack(id, false, answer);
    return;
  }
  if (id == msg::cfg_rst) {  // never acknowledged: the receiver resets
    reset(frame.payload, answer);
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
  std::vector<MessageId> touched;
  if (id == msg::cfg_msg && frame.payload.size() >= 2) touched.push_back({get_u1(frame.payload, 0), get_u1(frame.payload, 1)});
  Before b = before(std::move(touched));
  const bool ok = apply_cfg(frame, b);
  ack(id, ok, answer);
  if (ok) diff(b, answer);
}

void ConfigMachine::reset(std::string_view p, Answer& answer) {
  if (p.size() != 4) {
    ++stats_.ignored;
    return;
  }
  reset(get_u2(p, 0), get_u1(p, 2), answer);
}

Answer ConfigMachine::reset(std::uint16_t nav_bbr_mask, std::uint8_t reset_mode) {
  Answer answer;
  reset(nav_bbr_mask, reset_mode, answer);
  return answer;
}

void ConfigMachine::reset(std::uint16_t nav_bbr_mask, std::uint8_t reset_mode, Answer& answer) {
  discard_transaction();
  if (reloads_configuration(reset_mode)) {
    const Before b = before({}, true);
    settings_ = power_up(defaults_, stored_);
    ++stats_.resets;
    diff(b, answer);
  }
  if (nav_bbr_mask == 0xFFFF) answer.effects.emplace_back(ColdStart{});
}

bool ConfigMachine::answer_cfg_poll(const Frame& frame, Answer& answer) {
  const MessageId id = frame.id;
  const std::size_t size = frame.payload.size();
  if (id == msg::cfg_prt && size <= 1) {
    if (size == 1 && get_u1(frame.payload, 0) > static_cast<std::uint8_t>(Port::spi)) return false;  // NAKed as a write
    const Port port = size == 0 ? start_.port : static_cast<Port>(get_u1(frame.payload, 0));
    reply(answer, id, cfg_prt_payload(settings_, port));
  } else if (id == msg::cfg_msg && size == 2) {
    if (!model_has_message(start_.model, {get_u1(frame.payload, 0), get_u1(frame.payload, 1)})) return false;
    reply(answer, id, cfg_msg_payload(settings_, {get_u1(frame.payload, 0), get_u1(frame.payload, 1)}));
  } else if (id == msg::cfg_rate && size == 0) {
    reply(answer, id, cfg_rate_payload(settings_));
  } else if (id == msg::cfg_nav5 && size == 0) {
    reply(answer, id, settings_.nav5);
  } else if (id == msg::cfg_gnss && size == 0) {
    reply(answer, id, settings_.gnss);
  } else if (id == msg::cfg_sbas && size == 0) {
    reply(answer, id, settings_.sbas);
  } else {
    return false;
  }
  return true;
}

bool ConfigMachine::apply_cfg(const Frame& frame, Before& before) {
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
  if (id == msg::cfg_valset) return apply_valset(p, before);
  if (id == msg::cfg_valdel) return apply_valdel(p);
  if (id == msg::cfg_cfg) return apply_cfg_cfg(p, before);
  return !p.empty();  // another CFG write (TP5, PM2, ITFM...): accepted without an effect
}

void ConfigMachine::write_keys(const std::vector<std::pair<std::uint32_t, std::uint64_t>>& keys, std::uint8_t layer_bits,
                               Before& before) {
  if ((layer_bits & layer_bit_ram) != 0) {
    for (const auto& [key, value] : keys) {
      if (const auto m = msgout_of(key); m && m->second == start_.port &&
          std::none_of(before.rates.begin(), before.rates.end(), [&](const auto& r) { return r.first == m->first; })) {
        before.rates.emplace_back(m->first, settings_.rate(m->first, start_.port));
      }
      (void)set_key(settings_, key, value);  // validated: valset_keys()
    }
  }
  for (const std::uint8_t bit : {layer_bit_bbr, layer_bit_flash}) {
    if ((layer_bits & bit) == 0 || keys.empty()) continue;
    StoredLayer& layer = bit == layer_bit_bbr ? stored_.bbr : stored_.flash;
    for (const auto& [key, value] : keys) layer.keys[key] = value;
    ++stored_version_;
  }
}

bool ConfigMachine::apply_valset(std::string_view p, Before& before) {
  if (p.size() < 4) return false;
  const std::uint8_t version = get_u1(p, 0);
  const std::uint8_t layers = get_u1(p, 1);
  const std::uint8_t transaction = version == 1 ? get_u1(p, 2) : kTransactionNone;
  const bool valid_header = version <= 1 && layers != 0 && (layers & ~(layer_bit_ram | kStoredLayerBits)) == 0 &&
                            transaction <= kTransactionApply;
  auto keys = valid_header ? valset_keys(p) : std::nullopt;
  // A message key the model does not have: the whole VALSET is NAKed, nothing changes.
  if (keys) {
    const auto lacking = std::find_if(keys->begin(), keys->end(), [&](const auto& kv) { return !model_has_key(kv.first); });
    if (lacking != keys->end()) {
      nak_reason_ = fmt::format(": {}: a {} {} lacks", key_label(lacking->first),
                                msgout_message(lacking->first) ? "message" : "key", model_info(start_.model).name);
      keys.reset();
    }
  }
  if (!keys) {
    discard_transaction();
    return false;
  }
  switch (transaction) {
    case kTransactionNone:
      discard_transaction();  // a VALSET outside the transaction ends it unapplied
      write_keys(*keys, layers, before);
      return true;
    case kTransactionBegin:
      discard_transaction();
      transaction_ = Transaction{layers, std::move(*keys)};
      return true;
    case kTransactionContinue:
    case kTransactionApply:
    default:
      break;
  }
  if (!transaction_ || transaction_->layers != layers) {  // continue/apply without a begin, or other layers
    discard_transaction();
    return false;
  }
  std::vector<std::pair<std::uint32_t, std::uint64_t>>& staged = transaction_->keys;
  for (const auto& kv : *keys) {
    const auto same = std::find_if(staged.begin(), staged.end(), [&](const auto& s) { return s.first == kv.first; });
    if (same != staged.end()) {
      same->second = kv.second;
    } else {
      staged.push_back(kv);  // distinct known keys: bounded by the catalogue
    }
  }
  if (transaction == kTransactionApply) {
    const Transaction done = std::move(*transaction_);
    transaction_.reset();
    write_keys(done.keys, done.layers, before);
  }
  return true;
}

bool ConfigMachine::apply_valdel(std::string_view p) {
  if (p.size() < 4 || (p.size() - 4) % 4 != 0 || (p.size() - 4) / 4 > kMaxKeys) return false;
  const std::uint8_t layers = get_u1(p, 1);
  if (get_u1(p, 0) > 1 || (get_u1(p, 0) == 1 && get_u1(p, 2) != kTransactionNone)) return false;
  if (layers == 0 || (layers & ~kStoredLayerBits) != 0) return false;  // RAM cannot be deleted from
  for (std::size_t at = 4; at < p.size(); at += 4) {
    if (!is_known_key(get_u4(p, at))) return false;
  }
  for (const std::uint8_t bit : {layer_bit_bbr, layer_bit_flash}) {
    if ((layers & bit) == 0) continue;
    StoredLayer& layer = bit == layer_bit_bbr ? stored_.bbr : stored_.flash;
    for (std::size_t at = 4; at < p.size(); at += 4) {
      if (layer.keys.erase(get_u4(p, at)) != 0) ++stored_version_;
    }
  }
  return true;
}

bool ConfigMachine::apply_cfg_cfg(std::string_view p, Before& before) {
  if (p.size() != 12 && p.size() != 13) return false;
  const std::uint32_t clear_mask = get_u4(p, 0), save_mask = get_u4(p, 4), load_mask = get_u4(p, 8);
  // deviceMask: bit 0 BBR, bits 1, 2, 4 flash, EEPROM, SPI flash; without it BBR and flash.
  const std::uint8_t devices = p.size() == 13 ? get_u1(p, 12) : 0x03;
  const bool bbr = (devices & 0x01) != 0;
  const bool flash = (devices & 0x16) != 0;
  auto each = [&](auto&& f) {
    if (bbr) f(stored_.bbr);
    if (flash) f(stored_.flash);
  };
  if (clear_mask != 0) each([&](StoredLayer& l) { l = StoredLayer{}; ++stored_version_; });
  if (save_mask != 0) {
    const StoredLayer now = snapshot(settings_);
    each([&](StoredLayer& l) { l = now; ++stored_version_; });
  }
  if (load_mask != 0) {
    before = this->before({}, true);
    settings_ = power_up(defaults_, stored_);
  }
  return true;
}

void ConfigMachine::answer_valget(const Frame& frame, Answer& answer) {
  const std::string_view p = frame.payload;
  const std::uint8_t layer = p.size() >= 2 ? get_u1(p, 1) : 0xFF;
  const bool well_formed = p.size() >= 8 && (p.size() - 4) % 4 == 0 && (p.size() - 4) / 4 <= kMaxKeys &&
                           get_u1(p, 0) == 0 &&
                           (layer == layer_ram || layer == layer_bbr || layer == layer_flash || layer == layer_default);
  if (!well_formed) {
    ack(frame.id, false, answer);
    return;
  }
  const StoredLayer* stored = layer == layer_bbr ? &stored_.bbr : layer == layer_flash ? &stored_.flash : nullptr;
  const Settings& source = layer == layer_default ? defaults_ : settings_;
  std::string out;
  put_u1(out, 1);  // version: response
  put_u1(out, layer);
  put_u2(out, get_u2(p, 2));  // position
  std::size_t found = 0;
  for (std::size_t at = 4; at < p.size(); at += 4) {
    const std::uint32_t key = get_u4(p, at);
    if (is_wildcard(key) || key_value_bytes(key) == 0 || !model_has_key(key)) {
      ack(frame.id, false, answer);
      return;
    }
    std::optional<std::uint64_t> value;
    if (stored) {
      // A stored layer holds only what was written to it: other keys are left out of the answer.
      const auto it = stored->keys.find(key);
      if (it == stored->keys.end()) continue;
      value = it->second;
    } else {
      value = get_key(source, key);
      if (!value) {
        ack(frame.id, false, answer);
        return;
      }
    }
    put_u4(out, key);
    put_le(out, *value, static_cast<int>(key_value_bytes(key)));
    ++found;
  }
  if (found == 0) {
    ack(frame.id, false, answer);
    return;
  }
  reply(answer, msg::cfg_valget, out);
  ack(frame.id, true, answer);
}

bool ConfigMachine::model_has_key(std::uint32_t key) const {
  if (!model_has_key_group(start_.model, key)) return false;
  const std::optional<MessageId> id = msgout_message(key);
  return !id || model_has_message(start_.model, *id);
}

void ConfigMachine::diff(const Before& before, Answer& answer) const {
  const Port port = start_.port;
  if (before.period != settings_.output_period()) {
    answer.effects.emplace_back(MeasurementPeriodChanged{settings_.output_period()});
  }
  auto rate_changed = [&](MessageId id, std::uint8_t old_rate) {
    const std::uint8_t new_rate = settings_.rate(id, port);
    if (old_rate == new_rate) return;
    if (const auto type = sentence_of(id)) {
      if ((old_rate != 0) != (new_rate != 0)) answer.effects.emplace_back(NmeaSentenceChanged{*type, new_rate != 0});
    } else {
      answer.effects.emplace_back(MessageRateChanged{id, new_rate});
    }
  };
  if (before.all) {  // a load or a reset: every message
    std::set<MessageId> ids;
    for (const auto& [id, rates] : before.all->rates) ids.insert(id);
    for (const auto& [id, rates] : settings_.rates) ids.insert(id);
    for (const MessageId id : ids) rate_changed(id, before.all->rate(id, port));
  } else {
    for (const auto& [id, old_rate] : before.rates) rate_changed(id, old_rate);
  }
  const PortSettings& was = before.port;
  const PortSettings& now = settings_.ports[static_cast<std::size_t>(port)];
  if (was.out_proto_mask != now.out_proto_mask) {
    answer.effects.emplace_back(
        OutputProtocolsChanged{(now.out_proto_mask & proto_ubx) != 0, (now.out_proto_mask & proto_nmea) != 0});
  }
  if (was.baud != now.baud && now.baud != 0) answer.effects.emplace_back(BaudChanged{now.baud});
}

}  // namespace gpsemu::ubx
