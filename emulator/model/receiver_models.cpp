// The receiver table (see receiver_models.hpp). Firmware versions are those real modules report.
#include "emulator/model/receiver_models.hpp"

#include <array>

namespace gpsemu {
namespace {

using S = nmea::GnssSystem;
using std::chrono::milliseconds;

constexpr sky::SystemSet kM8Systems{S::gps, S::glonass, S::qzss, S::sbas};
// Four concurrent systems (GPS, GLONASS, Galileo, BeiDou) with QZSS and SBAS.
constexpr sky::SystemSet kFourSystems{S::gps, S::glonass, S::galileo, S::beidou, S::qzss, S::sbas};

sky::Tracking tracking(sky::SystemSet systems, bool dual_band, int channels, double uere_m) {
  sky::Tracking t;
  t.systems = systems;
  t.dual_band = dual_band;
  t.channels = channels;
  t.uere_m = uere_m;
  return t;
}

/// What a u-blox writes: RMC, VTG, GGA, GSA, GSV, GLL, GST, ZDA (heading is in NAV-RELPOSNED).
constexpr nmea::SentenceSet ublox_nmea() {
  nmea::SentenceSet s = nmea::SentenceSet::ublox_default();
  s.insert(nmea::SentenceType::gst);
  s.insert(nmea::SentenceType::zda);
  return s;
}
constexpr nmea::SentenceSet kUbloxDefault = nmea::SentenceSet::ublox_default();
constexpr nmea::SentenceSet kUbloxNmea = ublox_nmea();

const std::array<ReceiverFacts, kReceiverModels>& table() {
  // name, vendor, module, firmware, tracking (systems, dual band, channels, UERE m), fastest
  // solution, corrections, moving base, clock, default baud, NMEA after a reset, NMEA it can write.
  static const std::array<ReceiverFacts, kReceiverModels> rows = {
      ReceiverFacts{"generic", "u-blox", "NEO-M8N", "SPG 3.01", tracking(kM8Systems, false, 72, 1.6),
                    milliseconds{25}, Corrections::rtk, false, ClockQuality{}, 9600, kUbloxDefault, kUbloxNmea},
      ReceiverFacts{"ublox-m8n", "u-blox", "NEO-M8N", "SPG 3.01", tracking(kM8Systems, false, 72, 1.6),
                    milliseconds{100}, Corrections::rtk, false, ClockQuality{}, 9600, kUbloxDefault, kUbloxNmea},
      ReceiverFacts{"ublox-m9n", "u-blox", "NEO-M9N", "SPG 4.04", tracking(kFourSystems, false, 92, 1.3),
                    milliseconds{40}, Corrections::dgnss, false, ClockQuality{}, 38400, kUbloxDefault, kUbloxNmea},
      ReceiverFacts{"ublox-f9p", "u-blox", "ZED-F9P", "HPG 1.32", tracking(kFourSystems, true, 184, 1.0),
                    milliseconds{50}, Corrections::rtk, true, ClockQuality{}, 38400, kUbloxDefault, kUbloxNmea},
      // The lower-power M10 platform: the M9N's systems on 72 channels, 10 Hz with all four.
      ReceiverFacts{"ublox-m10", "u-blox", "MAX-M10S", "SPG 5.10", tracking(kFourSystems, false, 72, 1.3),
                    milliseconds{100}, Corrections::none, false, ClockQuality{}, 9600, kUbloxDefault, kUbloxNmea},
  };
  return rows;
}

}  // namespace

std::span<const ReceiverFacts> receiver_table() { return table(); }

const ReceiverFacts& facts_of(ReceiverModel model) { return table()[static_cast<std::size_t>(model)]; }

std::optional<ReceiverModel> receiver_model_from_name(std::string_view name) {
  for (std::size_t i = 0; i < table().size(); ++i) {
    if (table()[i].name == name) return static_cast<ReceiverModel>(i);
  }
  return std::nullopt;
}

std::string receiver_model_names() {
  std::string names;
  for (const ReceiverFacts& row : table()) names += (names.empty() ? "" : ", ") + std::string(row.name);
  return names;
}

}  // namespace gpsemu
