// gpsemu-ublox-doc IN OUT: writes IN (docs/ublox.md) to OUT with its generated blocks rewritten
// from the UBX tables: the message table (messages.hpp), the payload layouts (layouts.hpp) and the
// configuration keys gpsemu models (cfg_keys.hpp, named from cfg_key_catalogue.hpp). A block runs
// from `<!-- generated: NAME -->` to `<!-- end generated: NAME -->`; the prose around it is kept.
// tools/update-ublox-doc runs it; the test docs.ublox_tables_are_current checks the page.
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include "emulator/ubx/cfg_key_catalogue.hpp"
#include "emulator/ubx/cfg_keys.hpp"
#include "emulator/ubx/messages.hpp"
#include "emulator/ubx/settings.hpp"

namespace {

using namespace gpsemu::ubx;

struct ModelColumn {
  std::string_view header;
  ReceiverModel model;
};
constexpr ModelColumn kColumns[] = {{"generic, `ublox-m8n`", ReceiverModel::ublox_m8n},
                                    {"`ublox-m9n`", ReceiverModel::ublox_m9n},
                                    {"`ublox-f9p`", ReceiverModel::ublox_f9p},
                                    {"`ublox-m10`", ReceiverModel::ublox_m10}};

std::string role_text(MessageRole role) {
  switch (role) {
    case MessageRole::solution: return "with each solution at its rate; once when polled";
    case MessageRole::report: return "when it happens";
    case MessageRole::poll: return "answered to a poll";
    case MessageRole::input: return "written by the client";
    case MessageRole::output: return "a rate is kept, nothing written";
  }
  return "";
}

std::string payload_size(const MessageRow& row) {
  if (row.fields.empty()) return "";
  if (row.block.empty()) return fmt::format("{}", layout_bytes(row.fields));
  return fmt::format("{} + {} n", layout_bytes(row.fields), layout_bytes(row.block));
}

std::string messages_block() {
  std::string out = "| message | class, id | written | ";
  for (const ModelColumn& c : kColumns) out += fmt::format("{} | ", c.header);
  out += "CFG-MSGOUT key (UART1; I2C, UART2, USB, SPI at -1, +1, +2, +3) | payload bytes |\n| ---";
  for (std::size_t i = 0; i < 4 + std::size(kColumns); ++i) out += " | ---";
  out += " |\n";
  for (const MessageRow& row : message_table()) {
    // An NMEA message whose sentence gpsemu formats is written at its rate, after the UBX messages.
    const bool sentence = sentence_of(row.id).has_value();
    out += fmt::format("| {} | 0x{:02X} 0x{:02X} | {} | ", row.name, row.id.msg_class, row.id.msg_id,
                       sentence ? "NMEA sentence with each solution at its rate" : role_text(row.role));
    for (const ModelColumn& c : kColumns) {
      out += !model_has_message(c.model, row.id)            ? "NAK"
             : row.role == MessageRole::output && !sentence ? "acknowledged, not written"
                                                            : "yes";
      out += " | ";
    }
    const auto key = msgout_key(row.id, Port::uart1);
    out += key ? fmt::format("`{}` 0x{:08X}", find_key(*key)->name, *key) : std::string{};
    out += fmt::format(" | {} |\n", payload_size(row));
  }
  return out;
}

std::string fields_text(Layout layout) {
  std::string out;
  for (const Field& f : layout) {
    if (!out.empty()) out += ", ";
    out += fmt::format("{} {}", f.name, field_type_name(f.type));
    if (f.count > 1) out += fmt::format("[{}]", f.count);
    if (!f.unit.empty()) out += fmt::format(" ({})", f.unit);
  }
  return out;
}

std::string payloads_block() {
  std::string out;
  for (const MessageRow& row : message_table()) {
    if (row.fields.empty()) continue;
    out += fmt::format("- **{}** ({} bytes): {}", row.name, payload_size(row), fields_text(row.fields));
    if (!row.block.empty()) out += fmt::format("; then per block: {}", fields_text(row.block));
    out += "\n";
  }
  return out;
}

std::string keys_block() {
  std::string out = "| key | id | type | scale | unit |\n| --- | --- | --- | --- | --- |\n";
  for_each_modelled_key([&](std::uint32_t id) {
    if (msgout_of(id)) return;  // in the message table
    const KeyInfo* k = find_key(id);
    if (k == nullptr) return;
    out += fmt::format("| `{}` | 0x{:08X} | {} | {} | {} |\n", k->name, id, k->type, k->scale, k->unit);
  });
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: gpsemu-ublox-doc IN OUT (docs/ublox.md with its generated blocks rewritten)\n");
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::fprintf(stderr, "gpsemu-ublox-doc: cannot read %s\n", argv[1]);
    return 2;
  }
  const std::map<std::string, std::function<std::string()>> blocks = {
      {"messages", messages_block}, {"payloads", payloads_block}, {"keys", keys_block}};
  std::ostringstream out;
  std::string line;
  std::string skipping;  // the block being replaced
  while (std::getline(in, line)) {
    if (!skipping.empty()) {
      if (line != fmt::format("<!-- end generated: {} -->", skipping)) continue;
      skipping.clear();
    }
    out << line << '\n';
    constexpr std::string_view kBegin = "<!-- generated: ";
    if (line.starts_with(kBegin) && line.ends_with(" -->")) {
      const std::string name = line.substr(kBegin.size(), line.size() - kBegin.size() - 4);
      const auto it = blocks.find(name);
      if (it == blocks.end()) {
        std::fprintf(stderr, "gpsemu-ublox-doc: %s: unknown generated block %s\n", argv[1], name.c_str());
        return 2;
      }
      out << it->second();
      skipping = name;
    }
  }
  if (!skipping.empty()) {
    std::fprintf(stderr, "gpsemu-ublox-doc: %s: block %s has no end marker\n", argv[1], skipping.c_str());
    return 2;
  }
  std::ofstream(argv[2]) << out.str();
  return 0;
}
