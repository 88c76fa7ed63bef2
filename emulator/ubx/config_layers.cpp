// The configuration layers of a u-blox (see config_layers.hpp).
#include "emulator/ubx/config_layers.hpp"

#include <charconv>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/cfg_keys.hpp"

namespace gpsemu::ubx {
namespace {

constexpr std::string_view kHeader = "gpsemu u-blox receiver state 1";

std::string hex_of(std::string_view bytes) {
  std::string out;
  for (const char c : bytes) out += fmt::format("{:02x}", static_cast<unsigned char>(c));
  return out;
}

std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t at = 0;
  while (at < line.size()) {
    while (at < line.size() && (line[at] == ' ' || line[at] == '\t' || line[at] == '\r')) ++at;
    const std::size_t begin = at;
    while (at < line.size() && line[at] != ' ' && line[at] != '\t' && line[at] != '\r') ++at;
    if (at > begin) words.push_back(line.substr(begin, at - begin));
  }
  return words;
}

std::uint64_t hex_number(std::string_view word, std::uint64_t max, std::size_t line_no) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v, 16);
  if (ec != std::errc{} || end != word.data() + word.size() || v > max) {
    throw std::invalid_argument(fmt::format("line {}: '{}' is not a hexadecimal number up to {:x}", line_no, word, max));
  }
  return v;
}

std::string bytes_of(std::string_view hex, std::size_t line_no) {
  if (hex.size() % 2 != 0 || hex.size() > 2 * 1024) {
    throw std::invalid_argument(fmt::format("line {}: '{}' is not a block of hexadecimal bytes", line_no, hex));
  }
  std::string out;
  for (std::size_t i = 0; i < hex.size(); i += 2) out.push_back(static_cast<char>(hex_number(hex.substr(i, 2), 0xFF, line_no)));
  return out;
}

void write_layer(std::string& out, std::string_view name, const StoredLayer& layer) {
  for (const auto& [key, value] : layer.keys) out += fmt::format("{} key {:08x} {:x}\n", name, key, value);
  for (const auto& [id, rates] : layer.keyless_rates) {
    out += fmt::format("{} rate {:02x} {:02x}", name, id.msg_class, id.msg_id);
    for (const std::uint8_t r : rates) out += fmt::format(" {:x}", r);
    out += '\n';
  }
  if (layer.nav5) out += fmt::format("{} nav5 {}\n", name, hex_of(*layer.nav5));
  if (layer.gnss) out += fmt::format("{} gnss {}\n", name, hex_of(*layer.gnss));
  if (layer.sbas) out += fmt::format("{} sbas {}\n", name, hex_of(*layer.sbas));
}

}  // namespace

StoredLayer snapshot(const Settings& s) {
  StoredLayer layer;
  for_each_modelled_key([&](std::uint32_t key) {
    if (const auto v = get_key(s, key)) layer.keys[key] = *v;
  });
  for (const auto& [key, value] : s.other_keys) layer.keys[key] = value;
  for (const auto& [id, rates] : s.rates) {
    if (!msgout_key(id, Port::i2c)) layer.keyless_rates[id] = rates;
  }
  layer.nav5 = s.nav5;
  layer.gnss = s.gnss;
  layer.sbas = s.sbas;
  return layer;
}

void apply_layer(Settings& s, const StoredLayer& layer) {
  if (layer.nav5) s.nav5 = *layer.nav5;
  if (layer.gnss) s.gnss = *layer.gnss;
  if (layer.sbas) s.sbas = *layer.sbas;
  for (const auto& [id, rates] : layer.keyless_rates) {
    for (std::size_t p = 0; p < port_count; ++p) s.set_rate(id, static_cast<Port>(p), rates[p]);
  }
  for (const auto& [key, value] : layer.keys) (void)set_key(s, key, value);  // a bad value keeps the layer below's
}

Settings power_up(const Settings& defaults, const StoredLayers& layers) {
  Settings s = defaults;
  apply_layer(s, layers.flash);
  apply_layer(s, layers.bbr);
  return s;
}

std::string to_text(const StoredLayers& layers, ReceiverModel model) {
  std::string out{kHeader};
  out += fmt::format("\nmodel {}\n", model_info(model).name);
  write_layer(out, "bbr", layers.bbr);
  write_layer(out, "flash", layers.flash);
  return out;
}

StoredLayers stored_layers_from_text(std::string_view text, ReceiverModel model) {
  StoredLayers layers;
  std::size_t line_no = 0;
  bool header = false;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    const std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++line_no;
    const std::vector<std::string_view> w = words_of(line);
    if (w.empty() || w[0].starts_with('#')) continue;
    if (!header) {
      if (line.substr(0, kHeader.size()) != kHeader) {
        throw std::invalid_argument(fmt::format("line 1: not a gpsemu receiver state (it starts '{}')", kHeader));
      }
      header = true;
      continue;
    }
    if (w[0] == "model") {
      if (w.size() != 2 || w[1] != model_info(model).name) {
        throw std::invalid_argument(fmt::format("line {}: the state is of {}, this receiver is {}", line_no,
                                                w.size() > 1 ? w[1] : "no model", model_info(model).name));
      }
      continue;
    }
    if ((w[0] != "bbr" && w[0] != "flash") || w.size() < 3) {
      throw std::invalid_argument(fmt::format("line {}: expected 'bbr|flash key|rate|nav5|gnss|sbas ...', got '{}'",
                                              line_no, line));
    }
    StoredLayer& layer = w[0] == "bbr" ? layers.bbr : layers.flash;
    if (w[1] == "key" && w.size() == 4) {
      const auto key = static_cast<std::uint32_t>(hex_number(w[2], 0xFFFFFFFF, line_no));
      if (key_value_bytes(key) == 0 || !is_known_key(key)) {
        throw std::invalid_argument(fmt::format("line {}: {:08x} is not a configuration key of a u-blox", line_no, key));
      }
      layer.keys[key] = hex_number(w[3], 0xFFFFFFFFFFFFFFFF, line_no);
    } else if (w[1] == "rate" && w.size() == 4 + port_count) {
      const MessageId id{static_cast<std::uint8_t>(hex_number(w[2], 0xFF, line_no)),
                         static_cast<std::uint8_t>(hex_number(w[3], 0xFF, line_no))};
      PortRates rates{};
      for (std::size_t p = 0; p < port_count; ++p) rates[p] = static_cast<std::uint8_t>(hex_number(w[4 + p], 0xFF, line_no));
      layer.keyless_rates[id] = rates;
    } else if (w[1] == "nav5" && w.size() == 3) {
      layer.nav5 = bytes_of(w[2], line_no);
      if (layer.nav5->size() != 36) throw std::invalid_argument(fmt::format("line {}: nav5 takes 36 bytes", line_no));
    } else if (w[1] == "gnss" && w.size() == 3) {
      layer.gnss = bytes_of(w[2], line_no);
      if (layer.gnss->size() < 4 || (layer.gnss->size() - 4) % 8 != 0) {
        throw std::invalid_argument(fmt::format("line {}: gnss takes 4 + 8 n bytes", line_no));
      }
    } else if (w[1] == "sbas" && w.size() == 3) {
      layer.sbas = bytes_of(w[2], line_no);
      if (layer.sbas->size() != 8) throw std::invalid_argument(fmt::format("line {}: sbas takes 8 bytes", line_no));
    } else {
      throw std::invalid_argument(fmt::format("line {}: cannot read '{}'", line_no, line));
    }
  }
  if (!header) throw std::invalid_argument(fmt::format("empty: a receiver state starts '{}'", kHeader));
  return layers;
}

}  // namespace gpsemu::ubx
