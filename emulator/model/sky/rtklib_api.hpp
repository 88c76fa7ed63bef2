// The few functions of Debian's RTKLIB (librtklib-dev 2.4.3 b34, libRTKLib.so) that the sky uses.
// The Debian package ships the library without a header, so they are declared here, by their C
// names, with RTKLIB's own structures passed as opaque pointers: nothing of RTKLIB leaves
// emulator/model/sky/orbits.cpp. Internal to the sky; include nowhere else.
#pragma once

#include <ctime>

namespace gpsemu::rtk {

/// RTKLIB's gtime_t: seconds of the C time_t scale (GPS time here) plus a fraction.
struct GTime {
  std::time_t time;
  double sec;
};

/// RTKLIB's navigation system bits (SYS_GPS ...).
inline constexpr int kSysGps = 0x01, kSysSbas = 0x02, kSysGlo = 0x04, kSysGal = 0x08, kSysQzs = 0x10,
                     kSysCmp = 0x20;
/// RTKLIB's largest satellite number in this build is below this (GPS 32, GLONASS 27, Galileo
/// 36, QZSS 10, BeiDou 63, IRNSS 14, SBAS 39 ...).
inline constexpr int kSatNumberLimit = 256;

}  // namespace gpsemu::rtk

extern "C" {
int satno(int sys, int prn);
int satsys(int sat, int* prn);
gpsemu::rtk::GTime gpst2time(int week, double sec);
int readrnx(const char* file, int rcv, const char* opt, void* obs, void* nav, void* sta);
void uniqnav(void* nav);
void freenav(void* nav, int opt);
int satpos(gpsemu::rtk::GTime time, gpsemu::rtk::GTime teph, int sat, int ephopt, const void* nav, double* rs,
           double* dts, double* var, int* svh);
double satazel(const double* pos, const double* e, double* azel);
double geodist(const double* rs, const double* rr, double* e);
void dops(int ns, const double* azel, double elmin, double* dop);
double geoidh(const double* pos);
void pos2ecef(const double* pos, double* r);
int tle_read(const char* file, void* tle);
int tle_name_read(const char* file, void* tle);
int tle_pos(gpsemu::rtk::GTime time, const char* name, const char* satno, const char* desig, const void* tle,
            const void* erp, double* rs);
}
