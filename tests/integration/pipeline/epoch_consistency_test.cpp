// One epoch, one value: for every receiver model, each protocol and each of the 14 fault kinds
// (and none), every epoch the channel writes agrees with itself across sentences and messages.
// The configuration is built as the program builds it (build_config, run_settings); the channel
// runs the receiver model, RTK and faults forward and encodes the result; the test decodes its
// bytes (NMEA by checksum, UBX by frame) and checks the cross-field rules in one place:
//   - satellites used: GGA = the PRNs GSA lists = NAV-PVT numSV = NAV-SOL numSV = NAV-SAT svUsed;
//   - DOPs (3-D fixes) = the geometry of the satellites listed used (GSV/GSA az/el, and NAV-SAT)
//     within 0.05; GGA HDOP = GSA HDOP = NAV-DOP hDOP; NAV-PVT pDOP = NAV-DOP pDOP;
//   - accuracy: NAV-PVT hAcc = hypot(GST sigma lat, lon), vAcc = GST sigma alt, NAV-COV's
//     diagonal = their squares;
//   - satellites in view: GSV's = NAV-SAT's;
//   - time: GGA's UTC = NAV-PVT's.
// An epoch a fault cut (garble), held back (latency) or silenced is left out and counted; every
// run must check most of its epochs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "emulator/config/config.hpp"
#include "emulator/model/sky/dop.hpp"
#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/run_settings.hpp"
#include "emulator/protocol/ublox/ublox_protocol.hpp"
#include "emulator/ubx/frame.hpp"
#include "tests/support/ubx_frames.hpp"

namespace gpsemu {
namespace {
namespace epoch_consistency_test {

constexpr int kEpochs = 30;

// ---- decoding one epoch's bytes ------------------------------------------------------------

std::vector<std::string> fields_of(const std::string& sentence) {
  std::vector<std::string> f;
  std::size_t start = 1;  // after '$'
  const std::size_t end = sentence.find('*');
  while (true) {
    const std::size_t comma = sentence.find(',', start);
    if (comma == std::string::npos || comma > end) {
      f.push_back(sentence.substr(start, end - start));
      return f;
    }
    f.push_back(sentence.substr(start, comma - start));
    start = comma + 1;
  }
}

/// The NMEA sentences of `bytes` whose checksum is right (a garbled one is left out).
std::vector<std::vector<std::string>> sentences_in(const std::string& bytes) {
  std::vector<std::vector<std::string>> out;
  std::size_t at = 0;
  while ((at = bytes.find('$', at)) != std::string::npos) {
    const std::size_t star = bytes.find('*', at);
    if (star == std::string::npos || star + 2 >= bytes.size()) break;
    unsigned sum = 0;
    bool printable = true;
    for (std::size_t i = at + 1; i < star; ++i) {
      const auto c = static_cast<unsigned char>(bytes[i]);
      printable = printable && c >= 0x20 && c < 0x7f && c != '$';
      sum ^= c;
    }
    unsigned given = 0;
    if (printable && std::sscanf(bytes.c_str() + star + 1, "%2x", &given) == 1 && given == sum) {
      out.push_back(fields_of(bytes.substr(at, star - at + 1)));
    }
    at += 1;
  }
  return out;
}

template <typename T>
T le(const std::string& p, std::size_t at) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v |= std::uint64_t(static_cast<unsigned char>(p[at + i])) << (8 * i);
  T out;
  if constexpr (sizeof(T) == 4 && std::is_floating_point_v<T>) {
    const auto bits = static_cast<std::uint32_t>(v);
    std::memcpy(&out, &bits, 4);
  } else {
    out = static_cast<T>(v);
  }
  return out;
}

nmea::GnssSystem system_of_nmea(int system_id) {
  using S = nmea::GnssSystem;
  switch (system_id) {
    case 2: return S::glonass;
    case 3: return S::galileo;
    case 4: return S::beidou;
    case 5: return S::qzss;
    default: return S::gps;  // GPS and SBAS: GPS time
  }
}
int system_id_of_talker(const std::string& talker) {
  if (talker == "GL") return 2;
  if (talker == "GA") return 3;
  if (talker == "GB" || talker == "BD") return 4;
  if (talker == "GQ") return 5;
  return 1;
}

struct Sat {
  int elevation_deg = 0, azimuth_deg = 0;
};

/// What one epoch said, each part as it came.
struct Decoded {
  int ggas = 0, pvts = 0;
  std::optional<int> gga_quality, gga_used;
  std::optional<double> gga_hdop;
  std::optional<std::string> gga_time;
  int gsa_mode = 0;
  std::vector<std::pair<int, int>> gsa_used;  ///< (system id, satellite id)
  std::optional<double> gsa_pdop, gsa_hdop, gsa_vdop;
  bool gsa_dops_agree = true;
  std::map<std::pair<int, int>, Sat> gsv;  ///< (system id, satellite id) -> where
  std::optional<double> gst_lat_m, gst_lon_m, gst_alt_m;
  std::optional<std::string> pvt, dop, sat, sol, cov;
};

Decoded decode(const std::string& bytes) {
  Decoded d;
  for (const auto& f : sentences_in(bytes)) {
    if (f[0].size() != 5) continue;
    const std::string talker = f[0].substr(0, 2), type = f[0].substr(2);
    if (type == "GGA" && f.size() >= 10) {
      ++d.ggas;
      d.gga_time = f[1];
      d.gga_quality = std::stoi(f[6]);
      d.gga_used = f[7].empty() ? 0 : std::stoi(f[7]);
      if (!f[8].empty()) d.gga_hdop = std::stod(f[8]);
    } else if (type == "GSA" && f.size() >= 18) {
      d.gsa_mode = std::stoi(f[2]);
      const int system_id = f.size() >= 19 && !f[18].empty() ? std::stoi(f[18], nullptr, 16) : 1;
      for (int i = 3; i <= 14; ++i) {
        if (!f[static_cast<std::size_t>(i)].empty()) d.gsa_used.emplace_back(system_id, std::stoi(f[static_cast<std::size_t>(i)]));
      }
      const double p = std::stod(f[15]), h = std::stod(f[16]), v = std::stod(f[17]);
      if (d.gsa_pdop && (*d.gsa_pdop != p || *d.gsa_hdop != h || *d.gsa_vdop != v)) d.gsa_dops_agree = false;
      d.gsa_pdop = p, d.gsa_hdop = h, d.gsa_vdop = v;
    } else if (type == "GSV" && f.size() >= 4) {
      const int system_id = system_id_of_talker(talker);
      for (std::size_t i = 4; i + 3 < f.size(); i += 4) {
        if (f[i].empty() || f[i + 1].empty() || f[i + 2].empty()) continue;
        d.gsv[{system_id, std::stoi(f[i])}] = {std::stoi(f[i + 1]), std::stoi(f[i + 2])};
      }
    } else if (type == "GST" && f.size() >= 9 && !f[6].empty()) {
      d.gst_lat_m = std::stod(f[6]);
      d.gst_lon_m = std::stod(f[7]);
      d.gst_alt_m = std::stod(f[8]);
    }
  }
  for (const ubx::Frame& fr : ubx::test::frames_in(bytes)) {
    if (fr.id == ubx::msg::nav_pvt) ++d.pvts, d.pvt = fr.payload;
    if (fr.id == ubx::msg::nav_dop) d.dop = fr.payload;
    if (fr.id == ubx::msg::nav_sat) d.sat = fr.payload;
    if (fr.id == ubx::msg::nav_sol) d.sol = fr.payload;
    if (fr.id == ubx::msg::nav_cov) d.cov = fr.payload;
  }
  return d;
}

// ---- the rules -----------------------------------------------------------------------------

struct Tally {
  int checked = 0, left_out = 0, three_d = 0;
  std::vector<std::string> broken;
  void fail(int epoch, const std::string& what) {
    if (broken.size() < 12) broken.push_back(fmt::format("epoch {}: {}", epoch, what));
  }
};

void expect_dops(const sky::Dops& geometry, double hdop, double vdop, double pdop, const char* where, int k, Tally& t) {
  if (std::abs(geometry.hdop - hdop) > 0.05 || std::abs(geometry.vdop - vdop) > 0.05 ||
      std::abs(geometry.pdop - pdop) > 0.05) {
    t.fail(k, fmt::format("{} DOPs h/v/p {:.2f}/{:.2f}/{:.2f}, the geometry of the used set {:.2f}/{:.2f}/{:.2f}", where,
                          hdop, vdop, pdop, geometry.hdop, geometry.vdop, geometry.pdop));
  }
}

void check_epoch(const Decoded& d, bool ubx, int k, Tally& t) {
  // A whole epoch, or it is left out (garbled, held back, silent).
  if (d.ggas != 1 || !d.gga_quality || !d.gsa_pdop || !d.gsa_dops_agree ||
      (ubx && (d.pvts != 1 || !d.dop || !d.sat || !d.sol || !d.cov))) {
    ++t.left_out;
    return;
  }
  ++t.checked;
  const bool fix = *d.gga_quality > 0;
  const int used = static_cast<int>(d.gsa_used.size());
  if (*d.gga_used != used) t.fail(k, fmt::format("GGA {} used, GSA lists {}", *d.gga_used, used));
  if (fix && d.gga_hdop && std::abs(*d.gga_hdop - *d.gsa_hdop) > 0.011) {
    t.fail(k, fmt::format("GGA HDOP {} GSA {}", *d.gga_hdop, *d.gsa_hdop));
  }
  const bool three_d = fix && d.gsa_mode == 3;
  if (three_d) {
    ++t.three_d;
    std::vector<sky::UsedSatellite> listed;
    for (const auto& [system_id, id] : d.gsa_used) {
      const auto it = d.gsv.find({system_id, id});
      if (it == d.gsv.end()) {
        t.fail(k, fmt::format("GSA lists {}:{}, GSV does not", system_id, id));
        continue;
      }
      listed.push_back({double(it->second.azimuth_deg), double(it->second.elevation_deg), system_of_nmea(system_id)});
    }
    expect_dops(sky::multi_clock_dops(listed), *d.gsa_hdop, *d.gsa_vdop, *d.gsa_pdop, "GSA", k, t);
  }
  if (!ubx) return;

  const std::string& pvt = *d.pvt;
  const int pvt_used = le<std::uint8_t>(pvt, 23);
  const int sol_used = le<std::uint8_t>(*d.sol, 47);
  const std::string& sat = *d.sat;
  const int in_view = le<std::uint8_t>(sat, 5);
  int sat_used = 0;
  std::vector<sky::UsedSatellite> used_sats;
  for (int i = 0; i < in_view; ++i) {
    const std::size_t b = 8 + 12 * static_cast<std::size_t>(i);
    if ((le<std::uint32_t>(sat, b + 8) & 0x08) == 0) continue;
    ++sat_used;
    const auto gnss = static_cast<nmea::GnssSystem>(le<std::uint8_t>(sat, b));
    used_sats.push_back({double(le<std::int16_t>(sat, b + 4)), double(le<std::int8_t>(sat, b + 3)), gnss});
  }
  if (pvt_used != used || sol_used != used || sat_used != used) {
    t.fail(k, fmt::format("used: GSA {}, NAV-PVT {}, NAV-SOL {}, NAV-SAT {}", used, pvt_used, sol_used, sat_used));
  }
  if (in_view != static_cast<int>(d.gsv.size())) {
    t.fail(k, fmt::format("in view: GSV {}, NAV-SAT {}", d.gsv.size(), in_view));
  }
  const std::string& dop = *d.dop;
  const double pdop = le<std::uint16_t>(dop, 6) * 0.01, vdop = le<std::uint16_t>(dop, 10) * 0.01,
               hdop = le<std::uint16_t>(dop, 12) * 0.01;
  if (fix && std::abs(hdop - *d.gsa_hdop) > 0.011) t.fail(k, fmt::format("NAV-DOP hDOP {} GSA {}", hdop, *d.gsa_hdop));
  if (std::abs(le<std::uint16_t>(pvt, 76) * 0.01 - pdop) > 0.011) t.fail(k, "NAV-PVT pDOP is not NAV-DOP's");
  if (three_d) expect_dops(sky::multi_clock_dops(used_sats), hdop, vdop, pdop, "NAV-SAT/NAV-DOP", k, t);
  if (fix && d.gst_lat_m) {
    const double h_acc_m = le<std::uint32_t>(pvt, 40) * 1e-3, v_acc_m = le<std::uint32_t>(pvt, 44) * 1e-3;
    if (std::abs(h_acc_m - std::hypot(*d.gst_lat_m, *d.gst_lon_m)) > 0.002 || std::abs(v_acc_m - *d.gst_alt_m) > 0.0015) {
      t.fail(k, fmt::format("NAV-PVT hAcc/vAcc {:.3f}/{:.3f} m, GST {:.3f}/{:.3f}/{:.3f}", h_acc_m, v_acc_m,
                            *d.gst_lat_m, *d.gst_lon_m, *d.gst_alt_m));
    }
    const std::string& cov = *d.cov;
    const double nn = le<float>(cov, 16), ee = le<float>(cov, 28), dd = le<float>(cov, 36);
    if (std::abs(std::sqrt(nn + ee) - h_acc_m) > 0.002 + 1e-3 * h_acc_m || std::abs(std::sqrt(dd) - v_acc_m) > 0.0015 + 1e-3 * v_acc_m) {
      t.fail(k, fmt::format("NAV-COV diagonal {:.4f}/{:.4f}/{:.4f} m², NAV-PVT hAcc {:.3f} vAcc {:.3f}", nn, ee, dd, h_acc_m,
                            v_acc_m));
    }
  }
  // The UTC time of the epoch: GGA hhmmss.ss against NAV-PVT hour, min, sec, nano.
  if (le<std::uint8_t>(pvt, 11) & 0x02) {
    const double nano_s = le<std::int32_t>(pvt, 16) * 1e-9;
    const int hour = le<std::uint8_t>(pvt, 8), minute = le<std::uint8_t>(pvt, 9), second = le<std::uint8_t>(pvt, 10);
    const std::string& g = *d.gga_time;
    if (g.size() >= 6) {
      const double gga_s = std::stoi(g.substr(0, 2)) * 3600.0 + std::stoi(g.substr(2, 2)) * 60.0 + std::stod(g.substr(4));
      const double pvt_s = hour * 3600.0 + minute * 60.0 + second + nano_s;
      if (std::abs(gga_s - pvt_s) > 0.006 && std::abs(std::abs(gga_s - pvt_s) - 86400.0) > 0.006) {
        t.fail(k, fmt::format("GGA time {} NAV-PVT {:02}:{:02}:{:02}+{:.3f}", g, hour, minute, second, nano_s));
      }
    }
  }
}

// ---- the runs ------------------------------------------------------------------------------

struct Case {
  std::string model;  ///< --receiver
  std::string fault;  ///< a [[fault]] table's keys past `kind`, or "" for none
  std::string kind;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string name = info.param.model + "_" + (info.param.kind.empty() ? "no_fault" : info.param.kind);
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

const std::vector<std::pair<std::string, std::string>>& fault_kinds() {
  // Each kind's table: at 6 s for 14 s of a 30 s run at 1 Hz, strong enough to change what it changes.
  static const std::vector<std::pair<std::string, std::string>> kinds{
      {"", ""},
      {"outage", ""},
      {"freeze", ""},
      {"jump", "east_m = 30\ndecay_s = 5"},
      {"wrong", "north_m = 12\nramp_s = 3"},
      {"fix-quality", "quality = \"rtk-float\""},
      {"degrade", "satellites = 6\nramp_s = 4"},
      {"silence", ""},
      {"jam", "db = 24\nramp_s = 10"},
      {"sky-mask", "mask = \"urban-canyon\""},
      {"spoof", "speed_mps = 2\nbearing_deg = 90\neast_m = 20\nramp_s = 3"},
      {"time", "mode = \"jump\"\njump_s = 2.5"},
      {"reset", "silent_s = 1\nttff_s = 4"},
      {"garble", "rate = 0.05"},
      {"latency", "delay_ms = 250"},
  };
  return kinds;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const std::string model : {"generic", "ublox-m8n", "ublox-m9n", "ublox-f9p", "ublox-m10"}) {
    for (const auto& [kind, keys] : fault_kinds()) out.push_back({model, keys, kind});
  }
  return out;
}

class EpochConsistency : public ::testing::TestWithParam<Case> {};

TEST_P(EpochConsistency, EveryEpochAgreesAcrossSentencesAndMessages) {
  const Case& c = GetParam();
  std::string toml;
  // A reset is an event (it lasts silent_s + ttff_s); every other kind lasts 14 s.
  if (!c.kind.empty()) {
    toml = fmt::format("[[fault]]\nkind = \"{}\"\nat = 6\n{}{}\n", c.kind, c.kind == "reset" ? "" : "duration = 14\n", c.fault);
  }
  const bool ublox = c.model != "generic";
  RawOptions cli{{"receiver", {c.model}},
                 {"sentences", {"GGA,GSA,GSV,GST"}},
                 {"start-time", {"2026-11-28T14:00:00Z"}},
                 {"origin", {"-35.363261,149.165230,584"}},
                 {"rate", {"1"}},
                 {"duration", {std::to_string(kEpochs)}},
                 {"log-level", {"warn"}}};
  if (ublox) cli.push_back({"protocol", {"nmea+ubx"}});
  const Config config = build_config_from_text(toml, "consistency.toml", cli);
  RunSettings run = run_settings(config);
  ChannelSettings settings = run.receivers.at(0).channel;
  if (ublox) {
    // The u-blox port as a driver leaves it: the NAV messages the rules compare, every epoch.
    ubx::SessionSettings s;
    s.start.model = config.receiver().receiver_model;
    s.start.measurement_period = std::chrono::milliseconds(1000);
    s.start.sentences = settings.format.sentences;
    s.start.ubx_messages = {ubx::msg::nav_pvt, ubx::msg::nav_dop, ubx::msg::nav_sat, ubx::msg::nav_sol, ubx::msg::nav_cov};
    s.start.baud = 921600;
    s.format = settings.format;
    s.seed = settings.seed;
    settings.protocol = protocol::ublox_protocol(s);
  }
  const UtcNs t0 = parse_iso8601_utc("2026-11-28T14:00:00Z");
  Channel channel(settings, t0);
  const sources::Truth at_rest{{3.0, -2.0, 1.0}, {0.0, 0.0, 0.0}, std::nullopt, {}};
  Tally tally;
  for (int k = 0; k < kEpochs; ++k) {
    const ReceiverStats before = channel.stats();
    (void)channel.step(t0 + std::chrono::seconds(k), at_rest);
    const ReceiverStats& after = channel.stats();
    // A garbled or held-back epoch is not one epoch's whole bytes: the fault did what it says.
    if (after.epochs_garbled != before.epochs_garbled || after.epochs_delayed != before.epochs_delayed) {
      ++tally.left_out;
      continue;
    }
    check_epoch(decode(channel.bytes()), ublox, k, tally);
  }
  std::string broken;
  for (const auto& b : tally.broken) broken += "\n  " + b;
  EXPECT_TRUE(tally.broken.empty()) << c.model << " " << (c.kind.empty() ? "no fault" : c.kind) << ":" << broken;
  // Most epochs are whole (a silence, a reset's silent second, garbled or held-back epochs aside).
  EXPECT_GE(tally.checked, c.kind == "garble" || c.kind == "latency" ? 10 : kEpochs / 2) << tally.left_out << " left out";
  EXPECT_GE(tally.three_d, 5) << "3-D fixes checked against their geometry";
}

INSTANTIATE_TEST_SUITE_P(EveryModelAndFault, EpochConsistency, ::testing::ValuesIn(cases()), case_name);

}  // namespace epoch_consistency_test
}  // namespace
}  // namespace gpsemu
