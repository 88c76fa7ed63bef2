#include "emulator/calibration/receiver_state.hpp"

#include <algorithm>
#include <cmath>
#include <istream>
#include <map>
#include <set>
#include <vector>

#include <fmt/format.h>

#include "nmea/parse.hpp"

namespace gpsemu::calibration {
namespace {

std::optional<Spread> spread_of(std::vector<double> v) {
  if (v.empty()) return std::nullopt;
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))]; };
  return Spread{at(0.5), at(0.1), at(0.9), v.size()};
}

std::optional<double> number(const std::vector<std::string>& f, std::size_t i) {
  if (i >= f.size() || f[i].empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(f[i].c_str(), &end);
  if (end == f[i].c_str() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// A GSV satellite's key: its talker (system) and NMEA ID. GSA lists IDs without a talker when it
/// is GN; its 4.1 system ID names the system then.
std::string key(std::string_view system, int id) { return fmt::format("{}{}", system, id); }

std::string_view system_of_gsv(std::string_view talker, int id) {
  if (talker == "GP" || talker == "GN") return id >= 65 && id <= 96 ? "GL" : "GP";
  return talker;
}

std::string_view system_of_gsa(const nmea::Sentence& s, int id) {
  static constexpr std::string_view by_id[] = {"", "GP", "GL", "GA", "GB", "GQ"};
  if (s.fields.size() >= 18) {
    const auto sys = number(s.fields, 17);
    if (sys && *sys >= 1 && *sys <= 5) return by_id[static_cast<int>(*sys)];
  }
  return system_of_gsv(s.talker, id);
}

/// The --fix-quality name of a GGA quality (1, 2, 4, 5).
const char* quality_key(int quality) {
  switch (quality) {
    case 2: return "dgps";
    case 4: return "rtk-fixed";
    case 5: return "rtk-float";
    default: return "gps";
  }
}

}  // namespace

namespace {

/// The state learned sentence by sentence: memory follows the epochs (a few numbers each), never
/// the log's bytes.
class Learner {
 public:
  void take(const nmea::Sentence& s) {
    if (s.type == "GGA") {
      const auto quality = number(s.fields, 5);
      if (quality && *quality > 0) {
        ++qualities_[static_cast<int>(*quality)];
        if (const auto n = number(s.fields, 6)) used_.push_back(*n);
        if (const auto h = number(s.fields, 7); h && *h > 0 && *h < 99) hdop_.push_back(*h);
      }
      for (const std::string& k : used_ids_) {
        const auto e = elevation_.find(k);
        if (e != elevation_.end() && e->second > 0.0) lowest_used_ = lowest_used_ ? std::min(*lowest_used_, e->second) : e->second;
      }
      used_ids_.clear();
      pdop_taken_ = false;
    } else if (s.type == "GST") {
      const auto lat = number(s.fields, 5), lon = number(s.fields, 6);
      if (lat && lon && *lat > 0 && *lon > 0 && *lat < 9999 && *lon < 9999) gst_h_.push_back(std::hypot(*lat, *lon));
    } else if (s.type == "GSA" && s.fields.size() >= 17) {
      const auto mode = number(s.fields, 1);
      if (!mode || *mode < 2) return;
      for (std::size_t i = 2; i < 14; ++i) {
        if (const auto id = number(s.fields, i)) used_ids_.insert(key(system_of_gsa(s, static_cast<int>(*id)), static_cast<int>(*id)));
      }
      if (!pdop_taken_) {
        if (const auto p = number(s.fields, 14); p && *p > 0 && *p < 99) pdop_.push_back(*p);
        pdop_taken_ = true;
      }
    } else if (s.type == "GSV") {
      for (std::size_t i = 3; i + 2 < s.fields.size(); i += 4) {
        const auto id = number(s.fields, i);
        if (!id) continue;
        const auto el = number(s.fields, i + 1);
        if (el) elevation_[key(system_of_gsv(s.talker, static_cast<int>(*id)), static_cast<int>(*id))] = *el;
        if (const auto c = number(s.fields, i + 3); c && *c > 0) cn0_.push_back(*c);
      }
    }
  }
  void feed(nmea::StreamReader& reader, std::string_view bytes) {
    for (const nmea::Sentence& s : reader.feed(bytes)) take(s);
  }
  ReceiverState finish(nmea::StreamReader& reader) {
    if (auto last = reader.finish()) take(*last);
    ReceiverState st;
    st.satellites_used = spread_of(std::move(used_));
    st.hdop = spread_of(std::move(hdop_));
    st.pdop = spread_of(std::move(pdop_));
    st.cn0_dbhz = spread_of(std::move(cn0_));
    st.lowest_used_elevation_deg = lowest_used_;
    st.gst_sigma_h_m = spread_of(std::move(gst_h_));
    std::size_t most = 0;
    for (const auto& [q, n] : qualities_) {
      if ((q == 1 || q == 2 || q == 4 || q == 5) && n > most) {
        most = n;
        st.fix_quality = q;
      }
    }
    return st;
  }

 private:
  std::vector<double> used_, hdop_, pdop_, cn0_, gst_h_;
  std::map<int, std::size_t> qualities_;  // GGA fix quality -> epochs
  std::map<std::string, double> elevation_;  // the latest GSV elevation of each satellite
  std::set<std::string> used_ids_;           // GSA's used satellites since the last GGA
  std::optional<double> lowest_used_;
  bool pdop_taken_ = false;
};

}  // namespace

ReceiverState learn_receiver_state(std::string_view bytes) {
  nmea::StreamReader reader;
  Learner learner;
  learner.feed(reader, bytes);
  return learner.finish(reader);
}

ReceiverState learn_receiver_state(std::istream& log) {
  nmea::StreamReader reader;
  Learner learner;
  std::string chunk(1 << 20, '\0');  // 1 MiB at a time, as the calibration reads the log
  while (log) {
    log.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto n = static_cast<std::size_t>(log.gcount());
    if (n == 0) break;
    learner.feed(reader, std::string_view(chunk).substr(0, n));
  }
  return learner.finish(reader);
}

ReceiverState with_sigmas(ReceiverState state, double sigma_h_m, double model_sigma_h_m) {
  if (state.hdop && state.hdop->median > 0.0 && sigma_h_m > 0.0) {
    state.uere_m = std::clamp(sigma_h_m / state.hdop->median, 0.05, 50.0);
  }
  const double claimed_m = state.gst_sigma_h_m ? state.gst_sigma_h_m->median : sigma_h_m;
  if (claimed_m > 0.0 && model_sigma_h_m > 0.0) state.accuracy_ratio = std::clamp(claimed_m / model_sigma_h_m, 0.01, 10.0);
  if (model_sigma_h_m > 0.0) state.model_sigma_h_m = model_sigma_h_m;
  return state;
}

std::string receiver_state_toml(const ReceiverState& s) {
  std::string out;
  const auto spread = [](const char* what, const std::optional<Spread>& v, int decimals) {
    if (!v) return fmt::format("# {}: not in the log\n", what);
    return fmt::format("# {}: median {:.{}f}, 10-90% {:.{}f}..{:.{}f} ({} values)\n", what, v->median, decimals, v->p10,
                       decimals, v->p90, decimals, v->count);
  };
  out += "# The receiver's state in the log (GGA, GSA, GSV):\n";
  out += spread("satellites used", s.satellites_used, 0);
  out += spread("HDOP", s.hdop, 2);
  out += spread("PDOP", s.pdop, 2);
  out += spread("C/N0 dB-Hz", s.cn0_dbhz, 0);
  if (s.lowest_used_elevation_deg) {
    out += fmt::format("# lowest elevation used: {:.0f} degrees\n", *s.lowest_used_elevation_deg);
    out += fmt::format("elevation-mask = {:.0f}\n", std::clamp(std::floor(*s.lowest_used_elevation_deg), 0.0, 60.0));
  }
  if (s.uere_m) {
    out += "# UERE = the position's horizontal sigma / median HDOP: reported accuracy = HDOP x UERE\n";
    out += fmt::format("uere = {:.3f}\n", *s.uere_m);
  }
  if (s.fix_quality && *s.fix_quality != 1) {
    out += fmt::format("# the log's fix quality is {} (GGA): its noise is the receiver's at that quality, reported as it\n",
                       *s.fix_quality);
    out += fmt::format("fix-quality = \"{0}\"\nnoise-quality = \"{0}\"\n", quality_key(*s.fix_quality));
  }
  if (s.accuracy_ratio && s.model_sigma_h_m) {
    if (s.gst_sigma_h_m) {
      out += fmt::format("# the receiver claims (GST's horizontal sigma, median) {:.3f} m; the model's error is {:.3f} m "
                         "over a long run: reported accuracy = that error x this\n",
                         s.gst_sigma_h_m->median, *s.model_sigma_h_m);
    } else {
      out += fmt::format("# no GST: the receiver is taken to claim the scatter its log shows ({:.3f} m); the model's error "
                         "is {:.3f} m over a long run: reported accuracy = that error x this\n",
                         *s.accuracy_ratio * *s.model_sigma_h_m, *s.model_sigma_h_m);
    }
    out += fmt::format("accuracy-ratio = {:.3f}\n", *s.accuracy_ratio);
  }
  if (s.satellites_used) {
    out += "# at most the log's median of satellites used (the sky's geometry gives the DOPs)\n";
    out += fmt::format("satellites = {}\n", std::clamp(static_cast<int>(std::lround(s.satellites_used->median)), 4, 64));
  }
  return out;
}

std::string receiver_state_summary(const ReceiverState& s) {
  std::string out = "receiver state:";
  if (s.satellites_used) out += fmt::format(" {:.0f} satellites used ({:.0f}..{:.0f})", s.satellites_used->median, s.satellites_used->p10, s.satellites_used->p90);
  if (s.hdop) out += fmt::format(", HDOP {:.2f} ({:.2f}..{:.2f})", s.hdop->median, s.hdop->p10, s.hdop->p90);
  if (s.pdop) out += fmt::format(", PDOP {:.2f}", s.pdop->median);
  if (s.cn0_dbhz) out += fmt::format(", C/N0 {:.0f} dB-Hz ({:.0f}..{:.0f})", s.cn0_dbhz->median, s.cn0_dbhz->p10, s.cn0_dbhz->p90);
  if (s.lowest_used_elevation_deg) out += fmt::format(", lowest elevation used {:.0f} deg", *s.lowest_used_elevation_deg);
  if (s.uere_m) out += fmt::format(", UERE {:.2f} m", *s.uere_m);
  if (s.fix_quality) out += fmt::format(", fix quality {} ({})", *s.fix_quality, quality_key(*s.fix_quality));
  if (s.accuracy_ratio) out += fmt::format(", accuracy ratio {:.2f}{}", *s.accuracy_ratio, s.gst_sigma_h_m ? " (GST)" : "");
  return out + "\n";
}

}  // namespace gpsemu::calibration
