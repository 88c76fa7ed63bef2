// The serial start-up check's widest epoch (emulator/pipeline/serial_line_check.hpp): sized on the
// model's worst case by system, each system in its own GSV group and GSA as the writer lists them,
// so no epoch of a real multi-GNSS sky is wider than what the check planned for.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <string>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/serial_line_check.hpp"
#include "emulator/sources/sim.hpp"
#include "nmea/line_budget.hpp"

namespace gpsemu {
namespace {
namespace serial_line_check_test {

using std::chrono::minutes;

const UtcNs kT0 = parse_iso8601_utc("2024-05-01T00:00:00Z");

ChannelSettings m8n_at(const Geodetic& origin) {
  ChannelSettings s;
  s.origin = origin;
  s.receiver.tracking = facts_of(ReceiverModel::ublox_m8n).tracking;  // GPS, GLONASS, QZSS, SBAS
  s.format.talker = "GN";  // as validate.cpp sets it for a multi-system model
  return s;
}

/// The widest epoch a channel wrote over a day, one epoch every `step`.
std::size_t widest_written(const ChannelSettings& settings, minutes step) {
  Channel channel(settings, kT0);
  channel.set_source(sources::make_sim_source("stationary", {}, channel.frame(), kT0));
  std::size_t widest = 0;
  for (UtcNs t = kT0; t < kT0 + std::chrono::hours{24}; t += step) {
    (void)channel.step(t);
    widest = std::max(widest, channel.bytes().size());
  }
  return widest;
}

TEST(WorstCaseEpochBytes, AnM8nIsSizedOnEachSystemsOwnGsvGroupsAndGsa) {
  const ChannelSettings s = m8n_at({43.0725, -89.4125, 260.0});
  const Geometry g = resolve_geometry(s.receiver);
  const std::size_t by_system = worst_case_epoch_bytes(s.format, g.in_view_by_system, g.satellites_used);
  // The start-up line's "bytes an epoch at most" and the check are the same figure.
  EXPECT_EQ(by_system, nmea::line_budget(s.format, g.in_view_by_system, g.satellites_used, 1.0).bytes_per_epoch);
  // Wider than the old assumption of 20 satellites in one GPS group, 12 used.
  const std::size_t one_group = nmea::line_budget(s.format, 20, 12, 1.0).bytes_per_epoch;
  EXPECT_GT(by_system, one_group);
  // Every epoch of the real sky (Madison, Wisconsin; Tokyo; Sydney) over a day fits it; the
  // one-group figure was too small for each (688 bytes against 744-905 written).
  for (const Geodetic& place : {Geodetic{43.0725, -89.4125, 260.0}, Geodetic{35.68, 139.77, 40.0},
                                Geodetic{-33.87, 151.21, 30.0}}) {
    const std::size_t written = widest_written(m8n_at(place), minutes{5});
    std::cout << "M8N at " << place.lat_deg << ", " << place.lon_deg << ": widest epoch " << written
              << " bytes; sized " << by_system << " (one group of 20: " << one_group << ")\n";
    EXPECT_LE(written, by_system) << "at " << place.lat_deg << ", " << place.lon_deg;
    EXPECT_GT(written, 600u) << "a day of an M8N's sky lists its satellites (GSV, GSA)";
    EXPECT_GT(written, one_group) << "the old figure was too small";
  }
}

TEST(WorstCaseEpochBytes, AnF9psSecondSignalsAreInIt) {
  ChannelSettings s = m8n_at({43.0725, -89.4125, 260.0});
  s.receiver.tracking = facts_of(ReceiverModel::ublox_f9p).tracking;
  s.format.gsv_second_signal = true;  // as validate.cpp sets it for a dual-band model
  const Geometry g = resolve_geometry(s.receiver);
  const std::size_t by_system = worst_case_epoch_bytes(s.format, g.in_view_by_system, g.satellites_used);
  const std::size_t written = widest_written(s, minutes{10});
  std::cout << "F9P at Madison: widest epoch " << written << " bytes; sized " << by_system << "\n";
  EXPECT_LE(written, by_system);
  EXPECT_GT(written, 800u) << "four systems on two signals";
}

}  // namespace serial_line_check_test
}  // namespace
}  // namespace gpsemu
