// The payload layouts of the UBX messages gpsemu writes, as the u-blox
// interface descriptions name their fields (M8 protocol 18, M9 SPG 4.04, F9
// HPG 1.32; offsets checked against gpsd's driver_ubx.c, PX4-GPSDrivers' ubx.h
// and ArduPilot's AP_GPS_UBLOX.h). A message with repeated blocks (NAV-SAT,
// NAV-SIG, ...) has a header layout and a block layout. The encoders fill them
// with PayloadWriter (fields.hpp); docs/ublox.md lists them
// (tools/update-ublox-doc). Pure data.
#pragma once

#include <array>

#include "emulator/ubx/fields.hpp"

namespace gpsemu::ubx::layout {

using enum FieldType;

inline constexpr std::array<Field, 33> nav_pvt{{
    {"iTOW", U4, 1, "ms"},
    {"year", U2, 1, "y"},
    {"month", U1, 1, "month"},
    {"day", U1, 1, "d"},
    {"hour", U1, 1, "h"},
    {"min", U1, 1, "min"},
    {"sec", U1, 1, "s"},
    {"valid", X1},
    {"tAcc", U4, 1, "ns"},
    {"nano", I4, 1, "ns"},
    {"fixType", U1},
    {"flags", X1},
    {"flags2", X1},
    {"numSV", U1},
    {"lon", I4, 1, "1e-7 deg"},
    {"lat", I4, 1, "1e-7 deg"},
    {"height", I4, 1, "mm"},
    {"hMSL", I4, 1, "mm"},
    {"hAcc", U4, 1, "mm"},
    {"vAcc", U4, 1, "mm"},
    {"velN", I4, 1, "mm/s"},
    {"velE", I4, 1, "mm/s"},
    {"velD", I4, 1, "mm/s"},
    {"gSpeed", I4, 1, "mm/s"},
    {"headMot", I4, 1, "1e-5 deg"},
    {"sAcc", U4, 1, "mm/s"},
    {"headAcc", U4, 1, "1e-5 deg"},
    {"pDOP", U2, 1, "0.01"},
    {"flags3", X2},
    {"reserved1", U1, 4},
    {"headVeh", I4, 1, "1e-5 deg"},
    {"magDec", I2, 1, "1e-2 deg"},
    {"magAcc", U2, 1, "1e-2 deg"},
}};
inline constexpr std::array<Field, 7> nav_posllh{{{"iTOW", U4, 1, "ms"},
                                                  {"lon", I4, 1, "1e-7 deg"},
                                                  {"lat", I4, 1, "1e-7 deg"},
                                                  {"height", I4, 1, "mm"},
                                                  {"hMSL", I4, 1, "mm"},
                                                  {"hAcc", U4, 1, "mm"},
                                                  {"vAcc", U4, 1, "mm"}}};
inline constexpr std::array<Field, 9> nav_velned{{{"iTOW", U4, 1, "ms"},
                                                  {"velN", I4, 1, "cm/s"},
                                                  {"velE", I4, 1, "cm/s"},
                                                  {"velD", I4, 1, "cm/s"},
                                                  {"speed", U4, 1, "cm/s"},
                                                  {"gSpeed", U4, 1, "cm/s"},
                                                  {"heading", I4, 1, "1e-5 deg"},
                                                  {"sAcc", U4, 1, "cm/s"},
                                                  {"cAcc", U4, 1, "1e-5 deg"}}};
inline constexpr std::array<Field, 7> nav_status{{{"iTOW", U4, 1, "ms"},
                                                  {"gpsFix", U1},
                                                  {"flags", X1},
                                                  {"fixStat", X1},
                                                  {"flags2", X1},
                                                  {"ttff", U4, 1, "ms"},
                                                  {"msss", U4, 1, "ms"}}};
inline constexpr std::array<Field, 17> nav_sol{{{"iTOW", U4, 1, "ms"},
                                                {"fTOW", I4, 1, "ns"},
                                                {"week", I2},
                                                {"gpsFix", U1},
                                                {"flags", X1},
                                                {"ecefX", I4, 1, "cm"},
                                                {"ecefY", I4, 1, "cm"},
                                                {"ecefZ", I4, 1, "cm"},
                                                {"pAcc", U4, 1, "cm"},
                                                {"ecefVX", I4, 1, "cm/s"},
                                                {"ecefVY", I4, 1, "cm/s"},
                                                {"ecefVZ", I4, 1, "cm/s"},
                                                {"sAcc", U4, 1, "cm/s"},
                                                {"pDOP", U2, 1, "0.01"},
                                                {"reserved1", U1},
                                                {"numSV", U1},
                                                {"reserved2", U1, 4}}};
inline constexpr std::array<Field, 5> nav_posecef{{{"iTOW", U4, 1, "ms"},
                                                   {"ecefX", I4, 1, "cm"},
                                                   {"ecefY", I4, 1, "cm"},
                                                   {"ecefZ", I4, 1, "cm"},
                                                   {"pAcc", U4, 1, "cm"}}};
inline constexpr std::array<Field, 5> nav_velecef{{{"iTOW", U4, 1, "ms"},
                                                   {"ecefVX", I4, 1, "cm/s"},
                                                   {"ecefVY", I4, 1, "cm/s"},
                                                   {"ecefVZ", I4, 1, "cm/s"},
                                                   {"sAcc", U4, 1, "cm/s"}}};
inline constexpr std::array<Field, 8> nav_dop{{{"iTOW", U4, 1, "ms"},
                                               {"gDOP", U2, 1, "0.01"},
                                               {"pDOP", U2, 1, "0.01"},
                                               {"tDOP", U2, 1, "0.01"},
                                               {"vDOP", U2, 1, "0.01"},
                                               {"hDOP", U2, 1, "0.01"},
                                               {"nDOP", U2, 1, "0.01"},
                                               {"eDOP", U2, 1, "0.01"}}};
inline constexpr std::array<Field, 10> nav_timeutc{{{"iTOW", U4, 1, "ms"},
                                                    {"tAcc", U4, 1, "ns"},
                                                    {"nano", I4, 1, "ns"},
                                                    {"year", U2, 1, "y"},
                                                    {"month", U1, 1, "month"},
                                                    {"day", U1, 1, "d"},
                                                    {"hour", U1, 1, "h"},
                                                    {"min", U1, 1, "min"},
                                                    {"sec", U1, 1, "s"},
                                                    {"valid", X1}}};
inline constexpr std::array<Field, 6> nav_timegps{{{"iTOW", U4, 1, "ms"},
                                                   {"fTOW", I4, 1, "ns"},
                                                   {"week", I2},
                                                   {"leapS", I1, 1, "s"},
                                                   {"valid", X1},
                                                   {"tAcc", U4, 1, "ns"}}};
inline constexpr std::array<Field, 12> nav_timels{{{"iTOW", U4, 1, "ms"},
                                                   {"version", U1},
                                                   {"reserved0", U1, 3},
                                                   {"srcOfCurrLs", U1},
                                                   {"currLs", I1, 1, "s"},
                                                   {"srcOfLsChange", U1},
                                                   {"lsChange", I1, 1, "s"},
                                                   {"timeToLsEvent", I4, 1, "s"},
                                                   {"dateOfLsGpsWn", U2},
                                                   {"dateOfLsGpsDn", U2},
                                                   {"reserved1", U1, 3},
                                                   {"valid", X1}}};
inline constexpr std::array<Field, 5> nav_clock{{{"iTOW", U4, 1, "ms"},
                                                 {"clkB", I4, 1, "ns"},
                                                 {"clkD", I4, 1, "ns/s"},
                                                 {"tAcc", U4, 1, "ns"},
                                                 {"fAcc", U4, 1, "ps/s"}}};
inline constexpr std::array<Field, 14> nav_hpposllh{{{"version", U1},
                                                     {"reserved0", U1, 2},
                                                     {"flags", X1},
                                                     {"iTOW", U4, 1, "ms"},
                                                     {"lon", I4, 1, "1e-7 deg"},
                                                     {"lat", I4, 1, "1e-7 deg"},
                                                     {"height", I4, 1, "mm"},
                                                     {"hMSL", I4, 1, "mm"},
                                                     {"lonHp", I1, 1, "1e-9 deg"},
                                                     {"latHp", I1, 1, "1e-9 deg"},
                                                     {"heightHp", I1, 1, "0.1 mm"},
                                                     {"hMSLHp", I1, 1, "0.1 mm"},
                                                     {"hAcc", U4, 1, "0.1 mm"},
                                                     {"vAcc", U4, 1, "0.1 mm"}}};
inline constexpr std::array<Field, 17> nav_cov{{{"iTOW", U4, 1, "ms"},
                                                {"version", U1},
                                                {"posCovValid", U1},
                                                {"velCovValid", U1},
                                                {"reserved0", U1, 9},
                                                {"posCovNN", R4, 1, "m^2"},
                                                {"posCovNE", R4, 1, "m^2"},
                                                {"posCovND", R4, 1, "m^2"},
                                                {"posCovEE", R4, 1, "m^2"},
                                                {"posCovED", R4, 1, "m^2"},
                                                {"posCovDD", R4, 1, "m^2"},
                                                {"velCovNN", R4, 1, "m^2/s^2"},
                                                {"velCovNE", R4, 1, "m^2/s^2"},
                                                {"velCovND", R4, 1, "m^2/s^2"},
                                                {"velCovEE", R4, 1, "m^2/s^2"},
                                                {"velCovED", R4, 1, "m^2/s^2"},
                                                {"velCovDD", R4, 1, "m^2/s^2"}}};
inline constexpr std::array<Field, 1> nav_eoe{{{"iTOW", U4, 1, "ms"}}};
inline constexpr std::array<Field, 4> nav_sat{
    {{"iTOW", U4, 1, "ms"}, {"version", U1}, {"numSvs", U1}, {"reserved0", U1, 2}}};
inline constexpr std::array<Field, 7> nav_sat_block{{{"gnssId", U1},
                                                     {"svId", U1},
                                                     {"cno", U1, 1, "dBHz"},
                                                     {"elev", I1, 1, "deg"},
                                                     {"azim", I2, 1, "deg"},
                                                     {"prRes", I2, 1, "0.1 m"},
                                                     {"flags", X4}}};
inline constexpr std::array<Field, 4> nav_svinfo{
    {{"iTOW", U4, 1, "ms"}, {"numCh", U1}, {"globalFlags", X1}, {"reserved1", U1, 2}}};
inline constexpr std::array<Field, 8> nav_svinfo_block{{{"chn", U1},
                                                        {"svid", U1},
                                                        {"flags", X1},
                                                        {"quality", X1},
                                                        {"cno", U1, 1, "dBHz"},
                                                        {"elev", I1, 1, "deg"},
                                                        {"azim", I2, 1, "deg"},
                                                        {"prRes", I4, 1, "cm"}}};
inline constexpr std::array<Field, 4> nav_sig{
    {{"iTOW", U4, 1, "ms"}, {"version", U1}, {"numSigs", U1}, {"reserved0", U1, 2}}};
inline constexpr std::array<Field, 11> nav_sig_block{{{"gnssId", U1},
                                                      {"svId", U1},
                                                      {"sigId", U1},
                                                      {"freqId", U1},
                                                      {"prRes", I2, 1, "0.1 m"},
                                                      {"cno", U1, 1, "dBHz"},
                                                      {"qualityInd", U1},
                                                      {"corrSource", U1},
                                                      {"ionoModel", U1},
                                                      {"sigFlags", X2},
                                                      {"reserved1", U1, 4}}};
inline constexpr std::array<Field, 21> nav_relposned{{{"version", U1},
                                                      {"reserved0", U1},
                                                      {"refStationId", U2},
                                                      {"iTOW", U4, 1, "ms"},
                                                      {"relPosN", I4, 1, "cm"},
                                                      {"relPosE", I4, 1, "cm"},
                                                      {"relPosD", I4, 1, "cm"},
                                                      {"relPosLength", I4, 1, "cm"},
                                                      {"relPosHeading", I4, 1, "1e-5 deg"},
                                                      {"reserved1", U1, 4},
                                                      {"relPosHPN", I1, 1, "0.1 mm"},
                                                      {"relPosHPE", I1, 1, "0.1 mm"},
                                                      {"relPosHPD", I1, 1, "0.1 mm"},
                                                      {"relPosHPLength", I1, 1, "0.1 mm"},
                                                      {"accN", U4, 1, "0.1 mm"},
                                                      {"accE", U4, 1, "0.1 mm"},
                                                      {"accD", U4, 1, "0.1 mm"},
                                                      {"accLength", U4, 1, "0.1 mm"},
                                                      {"accHeading", U4, 1, "1e-5 deg"},
                                                      {"reserved2", U1, 4},
                                                      {"flags", X4}}};
inline constexpr std::array<Field, 5> rxm_rtcm{
    {{"version", U1}, {"flags", X1}, {"subType", U2}, {"refStation", U2}, {"msgType", U2}}};
inline constexpr std::array<Field, 17> mon_hw{{{"pinSel", X4},
                                               {"pinBank", X4},
                                               {"pinDir", X4},
                                               {"pinVal", X4},
                                               {"noisePerMS", U2},
                                               {"agcCnt", U2},
                                               {"aStatus", U1},
                                               {"aPower", U1},
                                               {"flags", X1},
                                               {"reserved1", U1},
                                               {"usedMask", X4},
                                               {"VP", U1, 17},
                                               {"jamInd", U1},
                                               {"reserved2", U1, 2},
                                               {"pinIrq", X4},
                                               {"pullH", X4},
                                               {"pullL", X4}}};
inline constexpr std::array<Field, 10> mon_hw2{{{"ofsI", I1},
                                                {"magI", U1},
                                                {"ofsQ", I1},
                                                {"magQ", U1},
                                                {"cfgSource", U1},
                                                {"reserved0", U1, 3},
                                                {"lowLevCfg", X4},
                                                {"reserved1", U1, 8},
                                                {"postStatus", X4},
                                                {"reserved2", U1, 4}}};
inline constexpr std::array<Field, 3> mon_rf{{{"version", U1}, {"nBlocks", U1}, {"reserved0", U1, 2}}};
inline constexpr std::array<Field, 14> mon_rf_block{{{"blockId", U1},
                                                     {"flags", X1},
                                                     {"antStatus", U1},
                                                     {"antPower", U1},
                                                     {"postStatus", X4},
                                                     {"reserved1", U1, 4},
                                                     {"noisePerMS", U2},
                                                     {"agcCnt", U2},
                                                     {"jamInd", U1},
                                                     {"ofsI", I1},
                                                     {"magI", U1},
                                                     {"ofsQ", I1},
                                                     {"magQ", U1},
                                                     {"reserved2", U1, 3}}};
inline constexpr std::array<Field, 2> mon_ver{{{"swVersion", CH, 30}, {"hwVersion", CH, 10}}};
inline constexpr std::array<Field, 1> mon_ver_block{{{"extension", CH, 30}}};

static_assert(layout_bytes(nav_pvt) == 92 && layout_bytes(nav_posllh) == 28 && layout_bytes(nav_velned) == 36);
static_assert(layout_bytes(nav_status) == 16 && layout_bytes(nav_sol) == 52 && layout_bytes(nav_posecef) == 20);
static_assert(layout_bytes(nav_velecef) == 20 && layout_bytes(nav_dop) == 18 && layout_bytes(nav_timeutc) == 20);
static_assert(layout_bytes(nav_timegps) == 16 && layout_bytes(nav_timels) == 24 && layout_bytes(nav_clock) == 20);
static_assert(layout_bytes(nav_hpposllh) == 36 && layout_bytes(nav_cov) == 64 && layout_bytes(nav_eoe) == 4);
static_assert(layout_bytes(nav_sat) == 8 && layout_bytes(nav_sat_block) == 12 && layout_bytes(nav_svinfo_block) == 12);
static_assert(layout_bytes(nav_sig) == 8 && layout_bytes(nav_sig_block) == 16 && layout_bytes(nav_relposned) == 64);
static_assert(layout_bytes(mon_hw) == 60 && layout_bytes(mon_hw2) == 28 && layout_bytes(mon_rf_block) == 24);
static_assert(layout_bytes(rxm_rtcm) == 8);

}  // namespace gpsemu::ubx::layout
