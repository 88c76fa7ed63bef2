// The observation body of an RTCM3 multiple signal message, MSM4 or MSM7 (RTCM 10403.3 §3.5.12),
// written from observations a base station has: per satellite its range (metres) and range rate,
// per signal the C/N0 and lock time. One encoder for every RTCM3 base of the project (the moving
// base's epoch, heading/rtcm3_base; the `gpsemu base` station, base/base_station). Pure: values in,
// payload bytes out (rtcm3_reader.hpp frames them).
//
// Header: DF002 DF003, the system's epoch time (msm_epoch_time), DF393 multiple message bit, DF409
// IODS, DF001 (7), DF411 DF412 DF417 DF418, satellite mask (64), signal mask (32), cell mask (every
// satellite on every signal). Satellite data: DF397 whole ms of the rough range, (MSM7: DF419
// extended info, the GLONASS frequency channel + 7) DF398 its 1/1024 ms, (MSM7: DF399 rough phase
// range rate, m/s). Cell data: MSM4 DF400 fine pseudorange (2^-24 ms), DF401 fine phaserange
// (2^-29 ms), DF402 lock time indicator, DF420 half-cycle, DF403 C/N0 (dB-Hz); MSM7 DF405 (2^-29 ms),
// DF406 (2^-31 ms), DF407 extended lock time, DF420, DF408 (2^-4 dB-Hz), DF404 fine phase range
// rate (0.0001 m/s). The phase range equals the pseudorange (no clocks, no ambiguity): a rover that
// differences them against its own sees consistent observations.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::rtk {

/// One satellite of an MSM.
struct MsmSatellite {
  int sv_id = 0;                 ///< its place in the satellite mask, 1..64 (GPS PRN, GLONASS slot, QZSS PRN - 192)
  double range_m = 0.0;          ///< pseudorange = phase range (metres), 0 < range < 255 light-ms
  double range_rate_mps = 0.0;   ///< phase range rate (m/s; MSM7 only)
  double cn0_dbhz = 0.0;         ///< carrier-to-noise density of every signal (dB-Hz)
  std::uint32_t lock_ms = 0;     ///< time the signals have been tracked without a slip (ms)
  std::optional<int> glonass_channel;  ///< GLONASS frequency channel -7..6 (MSM7 DF419; else 0)
};

/// One MSM4 or MSM7 message: every satellite observed on every signal.
struct MsmMessage {
  Gnss gnss = Gnss::gps;
  int msm = 4;                     ///< 4 or 7
  std::uint16_t station_id = 0;    ///< DF003, 0..4095
  std::uint32_t epoch_time = 0;    ///< msm_epoch_time()
  bool more_follow = false;        ///< DF393: more MSM of this epoch follow
  std::vector<int> signal_ids;     ///< DF395 ids 1..32 (msm_signal_ids()), ascending
  std::vector<MsmSatellite> satellites;  ///< any order; written by ascending sv_id
};

/// The message number of `gnss`'s MSM `msm` (1074 GPS MSM4, 1087 GLONASS MSM7, ...).
[[nodiscard]] std::uint16_t msm_message_type(Gnss gnss, int msm);
/// The system of a receiver's satellite; none for SBAS (no MSM from a base here).
[[nodiscard]] std::optional<Gnss> msm_gnss_of(nmea::GnssSystem system);
/// The signals a u-blox F9 base writes: L1 (GPS/QZSS 1C, GLONASS 1C, Galileo 1C, BeiDou B1I 2I)
/// and, `dual_band`, L2 (GPS/QZSS 2L, GLONASS 2C, Galileo E5b 7Q, BeiDou B2I 7I).
[[nodiscard]] std::vector<int> msm_signal_ids(Gnss gnss, bool dual_band);
/// The system's 30-bit epoch time at UTC `utc`: GPS/Galileo/QZSS ms of the GPS week, BeiDou ms of
/// the BDT week (GPS - 14 s), GLONASS day of week (3 bits, 0 Sunday) and ms of the Moscow day (27).
[[nodiscard]] std::uint32_t msm_epoch_time(Gnss gnss, nmea::UtcTime utc, int gps_minus_utc_s = 18);
/// DF402 (MSM4, 4 bits) and DF407 (MSM7, 10 bits) of a lock time in ms.
[[nodiscard]] unsigned msm_lock_indicator(std::uint32_t lock_ms);
[[nodiscard]] unsigned msm_lock_indicator_extended(std::uint32_t lock_ms);

/// The payload of `m`. Throws std::invalid_argument for an MSM other than 4 or 7, a satellite id
/// outside 1..64, a signal id outside 1..32, more than 64 cells or a range outside (0, 255) ms.
[[nodiscard]] std::string encode_msm_observations(const MsmMessage& m);

}  // namespace gpsemu::rtk
