#include "emulator/ui/snapshot.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "emulator/pipeline/rtk_receiver.hpp"
#include "emulator/model/accuracy.hpp"
#include "transport/pty_output.hpp"
#include "transport/tcp_output.hpp"

namespace gpsemu::ui {
namespace {

using nlohmann::json;

/// A number rounded to `decimals` (the page shows centimetres; the line stays short).
double rounded(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}

json enu_json(const Enu& m) {
  return {{"east_m", rounded(m.east_m, 3)}, {"north_m", rounded(m.north_m, 3)}, {"up_m", rounded(m.up_m, 3)}};
}

json optional_json(const std::optional<double>& value, int decimals) {
  return value ? json(rounded(*value, decimals)) : json(nullptr);
}

json fix_json(const nmea::Fix& fix) {
  json out{{"quality", static_cast<int>(fix.quality)},
           {"quality_name", quality_name(fix.quality)},
           {"dimension", fix.has_fix() ? (fix.dimension == nmea::FixDimension::two_d ? 2 : 3) : 0},
           {"satellites_used", fix.satellites_used},
           {"satellites_in_view", fix.satellites_in_view},
           {"time_valid", fix.time_valid},
           {"diff_age_s", optional_json(fix.diff_age_s, 1)}};
  if (!fix.has_fix()) return out;
  out.update(json{{"lat_deg", rounded(fix.lat_deg, 8)},
                  {"lon_deg", rounded(fix.lon_deg, 8)},
                  {"alt_msl_m", rounded(fix.alt_msl_m, 3)},
                  {"speed_mps", rounded(fix.speed_mps, 3)},
                  {"course_deg", optional_json(fix.course_deg_true, 1)},
                  {"hdop", rounded(fix.hdop, 2)},
                  {"vdop", rounded(fix.vdop, 2)},
                  {"pdop", rounded(fix.pdop, 2)},
                  {"tdop", rounded(fix.tdop, 2)},
                  {"gdop", rounded(fix.gdop, 2)},
                  {"h_acc_m", rounded(sky::horizontal_accuracy_m(fix), 3)},
                  {"v_acc_m", rounded(fix.sigma_alt_m, 3)},
                  {"gst_sigma_lat_m", rounded(fix.sigma_lat_m, 3)},
                  {"gst_sigma_lon_m", rounded(fix.sigma_lon_m, 3)},
                  {"gst_sigma_alt_m", rounded(fix.sigma_alt_m, 3)}});
  return out;
}

json satellites_json(const nmea::Fix& fix) {
  json out = json::array();
  for (int k = 0; k < fix.satellites_in_view; ++k) {
    const nmea::SatelliteInView& s = fix.satellites[static_cast<std::size_t>(k)];
    out.push_back({{"system", system_name(s.system)},
                   {"sv", s.sv_id},
                   {"prn", s.prn},
                   {"az_deg", s.azimuth_deg},
                   {"el_deg", s.elevation_deg},
                   {"cn0_dbhz", s.snr_dbhz ? json(*s.snr_dbhz) : json(nullptr)},
                   {"used", s.used}});
  }
  return out;
}

json sectors_json(const std::vector<SkyMaskSector>& sectors, const std::string& from) {
  json out = json::array();
  for (const SkyMaskSector& s : sectors) {
    out.push_back({{"from_azimuth_deg", s.from_azimuth_deg}, {"to_azimuth_deg", s.to_azimuth_deg},
                   {"min_elevation_deg", s.min_elevation_deg}, {"from", from}});
  }
  return out;
}

/// The elevation mask and the sky-mask sectors: --sky-mask's, and those of an active sky-mask fault.
json sky_json(const Channel& ch) {
  const ReceiverOptions& r = ch.settings().receiver;
  json mask = sectors_json(r.sky_mask, "--sky-mask");
  for (const faults::FaultTimeline::Entry& e : ch.faults().entries()) {
    const faults::SkyMask* sky_mask = e.fault.as<faults::SkyMask>();
    if (e.active && sky_mask) {
      for (json& s : sectors_json(sky_mask->mask, "fault")) mask.push_back(std::move(s));
    }
  }
  return {{"elevation_mask_deg", r.elevation_mask_deg.value_or(r.tracking.elevation_mask_deg)}, {"sky_mask", mask}};
}

json faults_json(const faults::FaultTimeline& t) {
  json out = json::array();
  const double now_s = t.last_epoch().since_s;
  for (const faults::FaultTimeline::Entry& e : t.entries()) {
    if (e.ended) continue;
    json f{{"fault", std::string(faults::kind_name(e.fault.kind()))}, {"describe", e.fault.describe()},
           {"active", e.active}, {"pending", false}, {"epochs", e.epochs}, {"remaining_s", nullptr}};
    if (e.active && e.fault.duration_s) f["remaining_s"] = rounded(std::max(0.0, e.fault.at_s + *e.fault.duration_s - now_s), 1);
    if (!e.cleared && t.clear_pending(e.fault.kind())) f["ends"] = "next epoch";
    out.push_back(std::move(f));
  }
  for (const faults::Fault& p : t.pending()) {
    out.push_back({{"fault", std::string(faults::kind_name(p.kind()))}, {"describe", p.parameters()}, {"active", false},
                   {"pending", true}, {"epochs", 0}, {"remaining_s", optional_json(p.duration_s, 1)}});
  }
  return out;
}

json link_json(const EpochView& v, const SnapshotContext& c) {
  json outputs = json::array();
  if (v.outputs) {
    for (const auto& o : *v.outputs) {
      json entry{{"name", o->describe()},
                 {"bytes_written", o->stats().bytes_written},
                 {"epochs_written", o->stats().epochs_written},
                 {"epochs_dropped", o->stats().epochs_dropped},
                 {"clients", nullptr}};
      if (const auto clients = o->clients_connected()) entry["clients"] = *clients;
      outputs.push_back(std::move(entry));
    }
  }
  return {{"outputs", outputs},
          {"bytes_per_s", rounded(c.bytes_per_s, 0)},
          {"line_baud", v.line.baud == 0 ? json(nullptr) : json(v.line.baud)},
          {"line_bytes_per_s", v.line.baud == 0 ? json(nullptr) : json(v.line.baud / 10)},
          {"tx_dropped_messages", v.line.dropped.messages},
          {"late_epochs", c.late_epochs},
          {"page_clients", c.page_clients},
          {"watch_clients", c.watch_clients}};
}

/// What a client configured (the protocol's own panel: a u-blox's rate, baud, messages), with the
/// line's baud beside it; null for a protocol nobody configures.
json protocol_json(const Channel& ch, const ReceiverLine& line) {
  const std::string text = ch.protocol().configuration_json();
  if (text.empty()) return nullptr;
  json out = json::parse(text);
  out["line_baud"] = line.baud == 0 ? json(nullptr) : json(line.baud);
  return out;
}

}  // namespace

std::optional<Enu> EpochError::error_m() const {
  if (!truth_m || !reported_m) return std::nullopt;
  return Enu{reported_m->east_m - truth_m->east_m, reported_m->north_m - truth_m->north_m, reported_m->up_m - truth_m->up_m};
}

std::optional<double> EpochError::horizontal_m() const {
  const auto e = error_m();
  return e ? std::optional<double>(std::hypot(e->east_m, e->north_m)) : std::nullopt;
}

std::optional<double> EpochError::vertical_m() const {
  const auto e = error_m();
  return e ? std::optional<double>(e->up_m) : std::nullopt;
}

EpochError epoch_error(const EpochView& view) {
  EpochError out;
  out.truth_m = view.channel.last_truth_m();
  if (view.fix.has_fix()) out.reported_m = view.channel.frame().to_enu({view.fix.lat_deg, view.fix.lon_deg, view.fix.alt_msl_m});
  return out;
}

std::string epoch_json(const EpochView& v, const EpochError& error, const SnapshotContext& c) {
  const Channel& ch = v.channel;
  const auto err = error.error_m();
  json out{{"class", "EPOCH"},
           {"receiver", v.receiver},
           {"receivers", c.receivers},
           {"epoch", c.epoch},
           {"time", format_iso8601_utc(v.t)},
           {"since_s", rounded(ch.faults().last_epoch().since_s, 3)},
           {"fix", fix_json(v.fix)},
           {"rtk", {{"state", v.fix.quality == nmea::FixQuality::rtk_fixed   ? "fixed"
                              : v.fix.quality == nmea::FixQuality::rtk_float ? "float"
                              : v.fix.quality == nmea::FixQuality::dgps      ? "dgps"
                                                                              : "none"},
                    {"correction_age_s", optional_json(v.fix.diff_age_s, 1)},
                    {"rtcm_messages", ch.rtk().counts().messages}}},
           {"truth", error.truth_m ? enu_json(*error.truth_m) : json(nullptr)},
           {"reported", error.reported_m ? enu_json(*error.reported_m) : json(nullptr)},
           {"error", err ? json{{"east_m", rounded(err->east_m, 3)},
                                {"north_m", rounded(err->north_m, 3)},
                                {"up_m", rounded(err->up_m, 3)},
                                {"horizontal_m", rounded(*error.horizontal_m(), 3)},
                                {"vertical_m", rounded(*error.vertical_m(), 3)}}
                         : json(nullptr)},
           {"satellites", satellites_json(v.fix)},
           {"sky", sky_json(ch)},
           {"faults", faults_json(ch.faults())},
           {"silent", ch.faults().last_epoch().silent},
           {"link", link_json(v, c)},
           {"ubx", protocol_json(ch, v.line)}};
  return out.dump(-1, ' ', false, json::error_handler_t::replace);
}

const char* system_name(nmea::GnssSystem system) {
  switch (system) {
    case nmea::GnssSystem::gps: return "GPS";
    case nmea::GnssSystem::sbas: return "SBAS";
    case nmea::GnssSystem::galileo: return "Galileo";
    case nmea::GnssSystem::beidou: return "BeiDou";
    case nmea::GnssSystem::qzss: return "QZSS";
    case nmea::GnssSystem::glonass: return "GLONASS";
  }
  return "?";
}

const char* quality_name(nmea::FixQuality quality) {
  switch (quality) {
    case nmea::FixQuality::none: return "none";
    case nmea::FixQuality::gps: return "gps";
    case nmea::FixQuality::dgps: return "dgps";
    case nmea::FixQuality::pps: return "pps";
    case nmea::FixQuality::rtk_fixed: return "rtk-fixed";
    case nmea::FixQuality::rtk_float: return "rtk-float";
    case nmea::FixQuality::estimated: return "estimated";
  }
  return "?";
}

}  // namespace gpsemu::ui
