#include "emulator/config/fleet_config.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "emulator/config/spec/output_spec.hpp"
#include "emulator/config/spec/rtcm_input_spec.hpp"
#include "emulator/config/validate.hpp"

namespace gpsemu {
namespace {

bool all_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

/// One thing a receiver writes to or listens on, which no other receiver may also use.
struct Claim {
  std::string resource;  ///< "pty link /tmp/gps1", "udp port 5601", ...: equal strings conflict
  std::string key;       ///< output | source | tee
  std::string raw;       ///< the setting before {i} was expanded
  std::string expanded;  ///< and after
  bool from_table = false;  ///< set by the receiver's [[receiver]] table (not the shared settings)
};

std::string normal_path(const std::filesystem::path& p) {
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(p, ec);
  return (ec ? p : absolute).lexically_normal().string();
}

/// What a written path resolves to: absolute, normal, symlinks followed, dangling ones too (./a,
/// a and a link to a are one file, whether a exists yet or not).
std::string resolved_path(const std::filesystem::path& p) {
  namespace fs = std::filesystem;
  fs::path path = normal_path(p);
  std::error_code ec;
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(path, ec)); ++hops) {
    const fs::path target = fs::read_symlink(path, ec);
    if (ec) break;
    path = normal_path(target.is_absolute() ? target : path.parent_path() / target);
  }
  const auto resolved = fs::weakly_canonical(path, ec);
  return ec ? path.string() : resolved.lexically_normal().string();
}

/// What an output claims, if anything (a pty without a link, tcp port 0: nothing shared).
std::optional<std::string> output_resource(const transport::OutputSpec& spec) {
  using K = transport::OutputKind;
  switch (spec.kind) {
    case K::pty:
      if (spec.path.empty()) return std::nullopt;
      return "pty link " + normal_path(spec.path);
    case K::file: return "file " + resolved_path(spec.path);
    case K::standard_output: return std::string("stdout");
    case K::serial:
      if (spec.usb) return "serial adapter " + transport::to_string(spec);
      return "serial device " + resolved_path(spec.path);
    case K::tcp:
      if (spec.port == 0) return std::nullopt;
      return fmt::format("tcp port {}", spec.port);
    case K::udp: return fmt::format("udp destination {}:{}", spec.host, spec.port);
  }
  return std::nullopt;
}

/// What a source holds, if anything (sim:, replay:FILE.csv, port 0: nothing shared).
std::optional<std::string> source_resource(const sources::SourceSpec& spec) {
  // A mavlink:tcp source connects: several receivers may follow one simulator.
  const bool listens = spec.is_socket() || spec.kind == sources::SourceKind::mavlink_udp;
  if (!listens || spec.endpoint.port == 0) return std::nullopt;
  const bool udp = spec.kind == sources::SourceKind::udp || spec.kind == sources::SourceKind::mavlink_udp;
  return fmt::format("{} port {}", udp ? "udp" : "tcp", spec.endpoint.port);
}

/// `raw` with a template in it, for the message that asks for one.
std::string suggest_template(const std::string& raw) {
  if (raw == "stdout") return "file:gps{i}.nmea";
  std::size_t digits = raw.size();
  while (digits > 0 && std::isdigit(static_cast<unsigned char>(raw[digits - 1])) != 0) --digits;
  if (digits < raw.size() && digits > 0 && raw[digits - 1] == ':') {
    return fmt::format("{}{{{}+i}}", raw.substr(0, digits), raw.substr(digits));  // a port: udp:{5600+i}
  }
  return raw + "{i}";
}

/// "receiver 2", "receiver 2 (DETAIL)", or with tables "receiver 2 ([[receiver]] at FILE:LINE, DETAIL)".
std::string who(const ConfigDraft& shared, int index, const std::string& detail = {}) {
  std::string where;
  if (!shared.receiver_tables.empty()) {
    const ReceiverTable& t = shared.receiver_tables[static_cast<std::size_t>(index)];
    where = fmt::format("[[receiver]] at {}:{}", t.file, t.line);
  }
  if (!where.empty() && !detail.empty()) where += ", ";
  where += detail;
  return where.empty() ? fmt::format("receiver {}", index) : fmt::format("receiver {} ({})", index, where);
}

void check_claims(const ConfigDraft& shared, const std::vector<std::vector<Claim>>& claims) {
  const int n = static_cast<int>(claims.size());
  std::map<std::string, std::pair<int, const Claim*>> owner;  // resource -> first receiver claiming it
  for (int i = 0; i < n; ++i) {
    for (const Claim& claim : claims[static_cast<std::size_t>(i)]) {
      const auto [it, inserted] = owner.try_emplace(claim.resource, i, &claim);
      if (inserted) continue;
      const auto& [first, first_claim] = it->second;
      const bool listens = claim.key == "source" || claim.key == "rtcm" || claim.resource.rfind("tcp port", 0) == 0;
      if (first == i) {  // one receiver: its bytes would go twice to one place (doubled or mangled)
        throw ConfigError(fmt::format(
            "{}{} '{}' and {} '{}' would both {} {}: give each output (and --tee) its own", n > 1 ? who(shared, i) + ": " : "",
            first_claim->key, first_claim->expanded, claim.key, claim.expanded, listens ? "listen on" : "write to",
            claim.resource));
      }
      if (!claim.from_table && !first_claim->from_table && claim.raw == first_claim->raw &&
          claim.raw.find('{') == std::string::npos) {
        throw ConfigError(fmt::format(
            "{} '{}' would be shared by all {} receivers ({} and {} would both {} {}): with several receivers, put "
            "{{i}} (the receiver's index) or {{B+i}} in it, e.g. {} '{}'{}",
            claim.key, claim.raw, n, who(shared, first), who(shared, i), listens ? "listen on" : "write to",
            claim.resource, claim.key, suggest_template(claim.raw),
            shared.receiver_tables.empty() ? "" : ", or give each [[receiver]] table its own"));
      }
      throw ConfigError(fmt::format(
          "{} and {} would both {} {}: give each receiver its own",
          who(shared, first, fmt::format("{} '{}'", first_claim->key, first_claim->expanded)),
          who(shared, i, fmt::format("{} '{}'", claim.key, claim.expanded)), listens ? "listen on" : "write to",
          claim.resource));
    }
  }
}

}  // namespace

std::string expand_receiver_template(const std::string& key, std::string_view text, int index) {
  std::string out;
  out.reserve(text.size() + 8);
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t open = text.find('{', pos);
    if (open == std::string_view::npos) {
      out.append(text.substr(pos));
      break;
    }
    out.append(text.substr(pos, open - pos));
    const std::size_t close = text.find('}', open);
    const std::string_view inner = close == std::string_view::npos ? std::string_view{} : text.substr(open + 1, close - open - 1);
    if (inner == "i") {
      out += std::to_string(index);
    } else if (inner.size() > 2 && inner.substr(inner.size() - 2) == "+i" && all_digits(inner.substr(0, inner.size() - 2)) &&
               inner.size() - 2 <= 9) {
      out += std::to_string(std::stoll(std::string(inner.substr(0, inner.size() - 2))) + index);
    } else {
      throw std::invalid_argument(fmt::format(
          "{} '{}': '{}' is not a receiver template (accepted: {{i}}, the receiver's index from 0, and {{B+i}}, "
          "B a whole number, e.g. udp:{{5600+i}})", key, text,
          close == std::string_view::npos ? text.substr(open) : text.substr(open, close - open + 1)));
    }
    pos = close + 1;
  }
  return out;
}

namespace {

/// Applies one [[receiver]] table's keys to `receiver` (a copy of the shared settings). Throws
/// ConfigError naming the file, line and key.
void apply_receiver_table(ReceiverDraft& receiver, const ReceiverTable& table) {
  ConfigDraft scratch;
  scratch.receiver = std::move(receiver);
  for (const auto& key : table.keys) {
    const OptionDef* option = find_option(key.name);
    try {
      if (!option) throw std::invalid_argument("unknown key");
      option->apply(scratch, key.values);
    } catch (const std::exception& e) {
      throw ConfigError(fmt::format("config file {}:{}: [[receiver]] key '{}': {}", table.file, key.line, key.name,
                                    e.what()));
    }
  }
  receiver = std::move(scratch.receiver);
}

/// The first spec that did not parse, thrown once the receivers' claims are checked.
struct SpecErrors {
  std::optional<std::string> source, output;
};

}  // namespace

std::vector<ReceiverSettings> resolve_receivers(const ConfigDraft& draft) {
  const bool tables = !draft.receiver_tables.empty();
  const int n = tables ? static_cast<int>(draft.receiver_tables.size()) : draft.receivers;
  std::vector<ReceiverSettings> fleet;
  fleet.reserve(static_cast<std::size_t>(n));
  std::vector<std::vector<Claim>> claims(static_cast<std::size_t>(n));
  SpecErrors errors;
  for (int i = 0; i < n; ++i) {
    ReceiverDraft d = draft.receiver;
    d.settings.seed = draft.receiver.settings.seed + static_cast<std::uint64_t>(i);
    const ReceiverTable* table = tables ? &draft.receiver_tables[static_cast<std::size_t>(i)] : nullptr;
    if (table) apply_receiver_table(d, *table);
    ReceiverSettings r;
    try {
      r = resolve_receiver(d, draft.timeline);
    } catch (const std::exception& e) {
      if (!table) throw;
      throw ConfigError(fmt::format("config file {}:{}: [[receiver]]: {}", table->file, table->line, e.what()));
    }
    auto& mine = claims[static_cast<std::size_t>(i)];
    const auto table_sets = [table](const char* key) {
      return table && std::any_of(table->keys.begin(), table->keys.end(),
                                  [key](const ReceiverTable::Key& k) { return k.name == key; });
    };
    try {
      for (const std::string& raw : d.outputs) {
        const std::string output = expand_receiver_template("output", raw, i);
        try {
          r.outputs.push_back(transport::parse_output_spec(output));
        } catch (const std::invalid_argument& e) {
          if (!errors.output) errors.output = e.what();
          continue;
        }
        if (auto c = output_resource(r.outputs.back())) mine.push_back({*c, "output", raw, output, table_sets("output")});
      }
      const std::string source = expand_receiver_template("source", d.source, i);
      try {
        r.source = sources::parse_source_spec(source);
        if (auto c = source_resource(r.source)) mine.push_back({*c, "source", d.source, source, table_sets("source")});
      } catch (const std::invalid_argument& e) {
        if (!errors.source) errors.source = e.what();
      }
      if (d.tee) {
        r.tee = expand_receiver_template("tee", *d.tee, i);
        mine.push_back({"file " + resolved_path(*r.tee), "tee", *d.tee, *r.tee, table_sets("tee")});
      }
      if (r.receiver_state) {  // a u-blox's stored layers: one file a receiver
        const std::string raw = *r.receiver_state;
        r.receiver_state = expand_receiver_template("receiver-state", raw, i);
        mine.push_back({"file " + resolved_path(*r.receiver_state), "receiver-state", raw, *r.receiver_state,
                        table_sets("receiver-state")});
      }
      if (d.rtcm) {  // a base station's stream: one listening port a receiver (docs/rtk.md)
        const std::string rtcm = expand_receiver_template("rtcm", *d.rtcm, i);
        r.rtcm = transport::parse_rtcm_input_spec(rtcm);
        if (r.rtcm->endpoint.port != 0) {
          mine.push_back({fmt::format("{} port {}", r.rtcm->tcp ? "tcp" : "udp", r.rtcm->endpoint.port), "rtcm", *d.rtcm,
                          rtcm, table_sets("rtcm")});
        }
      }
    } catch (const std::invalid_argument& e) {
      throw ConfigError(n > 1 ? fmt::format("{}: {}", who(draft, i), e.what()) : std::string(e.what()));
    }
    fleet.push_back(std::move(r));
  }
  check_claims(draft, claims);
  // A spec that does not parse, as opening it would have said (sources are opened first).
  if (errors.source) throw ConfigError(*errors.source);
  if (errors.output) throw ConfigError(*errors.output);
  link_moving_base_pairs(fleet);
  return fleet;
}

}  // namespace gpsemu
