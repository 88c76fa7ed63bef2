#include "emulator/model/sky/orbits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unistd.h>

#include "emulator/model/sky/embedded_data.hpp"
#include "emulator/model/sky/rtklib_api.hpp"

// RTKLIB calls these back from its readers; a program using libRTKLib.so provides them.
extern "C" {
int showmsg(const char*, ...) { return 0; }
void settspan(gpsemu::rtk::GTime, gpsemu::rtk::GTime) {}
void settime(gpsemu::rtk::GTime) {}
}

namespace gpsemu::sky {
namespace {

constexpr double kWeekS = 604800.0;
constexpr double kDayS = 86400.0;
// How finely the moments a satellite's records are valid at are searched: hourly (a received
// satellite's records cover it continuously, GLONASS's every 30 minutes, so an hour of reception
// is always found; finer searching cost start-up time, 30 ms at 15 minutes, for no other sky).
constexpr double kRecordSearchStepS = 3600.0;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// RTKLIB's nav_t is larger than a megabyte in this build; the buffer is zeroed pages that only
// grow resident as RTKLIB writes them. sizeof(nav_t) of Debian's 2.4.3 b34 is about 0.9 MB.
constexpr std::size_t kNavBufferBytes = 16u << 20;
// RTKLIB's tle_t: {int n, nmax; tled_t* data;} (its records stay opaque).
struct TleTable {
  int n = 0, nmax = 0;
  void* data = nullptr;
};

rtk::GTime to_gtime(GpsSeconds t) {
  const double week = std::floor(t / kWeekS);
  return gpst2time(static_cast<int>(week), t - week * kWeekS);
}

int rtklib_system(nmea::GnssSystem s) {
  switch (s) {
    case nmea::GnssSystem::gps: return rtk::kSysGps;
    case nmea::GnssSystem::sbas: return rtk::kSysSbas;
    case nmea::GnssSystem::galileo: return rtk::kSysGal;
    case nmea::GnssSystem::beidou: return rtk::kSysCmp;
    case nmea::GnssSystem::qzss: return rtk::kSysQzs;
    case nmea::GnssSystem::glonass: return rtk::kSysGlo;
  }
  return 0;
}

std::optional<nmea::GnssSystem> our_system(int rtklib_sys) {
  switch (rtklib_sys) {
    case rtk::kSysGps: return nmea::GnssSystem::gps;
    case rtk::kSysSbas: return nmea::GnssSystem::sbas;
    case rtk::kSysGal: return nmea::GnssSystem::galileo;
    case rtk::kSysCmp: return nmea::GnssSystem::beidou;
    case rtk::kSysQzs: return nmea::GnssSystem::qzss;
    case rtk::kSysGlo: return nmea::GnssSystem::glonass;
    default: return std::nullopt;  // IRNSS, LEO: no u-blox model here tracks them
  }
}

/// A name of TLE_GNSS_SATNO ("G01", "R05", "E11", "C20", "J02", "127") as a satellite.
std::optional<SatelliteId> id_of_tle_name(std::string_view name) {
  if (name.empty()) return std::nullopt;
  const char c = name.front();
  const bool letter = c >= 'A' && c <= 'Z';
  const int number = std::atoi(std::string(letter ? name.substr(1) : name).c_str());
  if (number <= 0) return std::nullopt;
  switch (c) {
    case 'G': return SatelliteId{nmea::GnssSystem::gps, number};
    case 'R': return SatelliteId{nmea::GnssSystem::glonass, number};
    case 'E': return SatelliteId{nmea::GnssSystem::galileo, number};
    case 'C': return SatelliteId{nmea::GnssSystem::beidou, number};
    case 'J': return SatelliteId{nmea::GnssSystem::qzss, number};
    default: break;
  }
  if (!letter && number >= 120 && number <= 158) return SatelliteId{nmea::GnssSystem::sbas, number};
  return std::nullopt;
}

/// A file RTKLIB can open by name holding `text` (RTKLIB's readers take paths): an unnamed
/// temporary file, reached through /proc/self/fd while it is open.
class TextFile {
 public:
  explicit TextFile(std::string_view text) : file_(std::tmpfile()) {
    if (!file_ || std::fwrite(text.data(), 1, text.size(), file_) != text.size() || std::fflush(file_) != 0) {
      throw std::runtime_error("sky: cannot write a temporary file for RTKLIB");
    }
    path_ = "/proc/self/fd/" + std::to_string(fileno(file_));
  }
  ~TextFile() { std::fclose(file_); }
  TextFile(const TextFile&) = delete;
  TextFile& operator=(const TextFile&) = delete;
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::FILE* file_;
  std::string path_;
};

/// The day a RINEX 2/3 navigation file covers (GPS seconds of its 00:00): the civil day of most of
/// its records (a daily file starts with a few records of the evening before), read from its text.
std::optional<GpsSeconds> coverage_day(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  bool body = false;
  double version = 0.0;
  std::map<long, int> records_per_day;
  while (std::getline(in, line)) {
    if (!body) {
      if (line.find("RINEX VERSION") != std::string::npos) version = std::atof(line.substr(0, 9).c_str());
      if (line.find("END OF HEADER") != std::string::npos) body = true;
      continue;
    }
    if (line.size() < 23 || line[0] == ' ') continue;  // continuation lines start with blanks
    int y = 0, mo = 0, d = 0;
    std::istringstream fields(version >= 3.0 ? line.substr(4, 19) : line.substr(2, 20));
    fields >> y >> mo >> d;
    if (!fields || mo < 1 || mo > 12 || d < 1 || d > 31) continue;
    if (y < 80) y += 2000; else if (y < 100) y += 1900;
    // Days since 1970-01-01 from the civil date.
    y -= mo <= 2;
    const int era = (y >= 0 ? y : y - 399) / 400;
    const int yoe = y - era * 400;
    const int doy = (153 * (mo + (mo > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    ++records_per_day[static_cast<long>(era) * 146097 + yoe * 365 + yoe / 4 - yoe / 100 + doy - 719468];
  }
  if (records_per_day.empty()) return std::nullopt;
  const auto most = std::max_element(records_per_day.begin(), records_per_day.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  return static_cast<double>(most->first - 3657) * kDayS;  // 1980-01-06 is day 3657 of the Unix epoch
}

/// `t` moved into the day starting at `start` at the same sidereal time (t itself when inside).
GpsSeconds same_sidereal_time(GpsSeconds t, GpsSeconds start) {
  if (t >= start && t < start + kDayS) return t;
  double offset = std::fmod(t - start, kSiderealDayS);
  if (offset < 0.0) offset += kSiderealDayS;
  return start + offset;
}

}  // namespace

struct Orbits::Impl {
  std::string description;
  GpsSeconds start = 0.0;               // the data's day (the RINEX file's when there is one)
  GpsSeconds tle_start = 0.0;           // the two-line elements' day
  std::vector<SatelliteId> satellites;
  std::vector<int> rtklib_sat;          // per satellite: RTKLIB satellite number, 0 for a TLE one
  std::vector<std::string> tle_name;    // per satellite: the name tle_pos finds it by ("" for RINEX)
  // RINEX, per satellite: the moments of the data's day (every kRecordSearchStepS) at which one of
  // its records is valid, sorted; where none is, the nearest one's record is extrapolated.
  std::vector<std::vector<GpsSeconds>> valid_at;
  void* nav = nullptr;                  // RINEX: RTKLIB nav_t (opaque)
  TleTable tle;                         // TLE: RTKLIB tle_t

  ~Impl() {
    if (nav) {
      freenav(nav, 0xFF);
      std::free(nav);
    }
    std::free(tle.data);
  }

  std::optional<EcefMotion> motion(std::size_t i, GpsSeconds t) const {
    double rs[6] = {0, 0, 0, 0, 0, 0};
    if (rtklib_sat[i] != 0) {
      const rtk::GTime time = to_gtime(t);
      double dts[2] = {0, 0}, var = 0.0;
      int svh = 0;
      const bool recorded = satpos(time, time, rtklib_sat[i], 0 /* EPHOPT_BRDC */, nav, rs, dts, &var, &svh) != 0;
      if (recorded && svh != 0) return std::nullopt;  // unhealthy: left out
      if (!recorded) {
        // No record valid now (a station's file holds a satellite's records only while the station
        // saw it): the orbit of the nearest moment that has one, extrapolated. Hours off, a
        // broadcast orbit is kilometres off, hundredths of a degree seen from the ground: a
        // plausible sky everywhere, which is what the file stands for.
        if (i >= valid_at.size() || valid_at[i].empty()) return std::nullopt;
        const std::vector<GpsSeconds>& moments = valid_at[i];
        const auto after = std::lower_bound(moments.begin(), moments.end(), t);
        GpsSeconds nearest = after == moments.end() ? moments.back() : *after;
        if (after != moments.begin() && (after == moments.end() || t - *(after - 1) < *after - t)) nearest = *(after - 1);
        svh = 0;
        if (!satpos(time, to_gtime(nearest), rtklib_sat[i], 0, nav, rs, dts, &var, &svh) || svh != 0) return std::nullopt;
      }
    } else {
      // Elements of another day than the RINEX file's: the moment of their day with the same
      // sidereal time, so the Earth has the same orientation under them.
      const rtk::GTime time = to_gtime(same_sidereal_time(t, tle_start));
      if (!tle_pos(time, tle_name[i].c_str(), "", "", &tle, nullptr, rs)) return std::nullopt;
    }
    if (rs[0] == 0.0 && rs[1] == 0.0 && rs[2] == 0.0) return std::nullopt;
    return EcefMotion{{rs[0], rs[1], rs[2]}, rs[3], rs[4], rs[5]};
  }

  /// Keeps the satellites with an orbit at some hour of the day: RTKLIB numbers `sats` (RINEX)
  /// or the names `names` (TLE), one of them empty.
  void keep_satellites_with_orbits(const std::vector<SatelliteId>& ids, const std::vector<int>& sats,
                                   const std::vector<std::string>& names) {
    for (std::size_t i = 0; i < ids.size(); ++i) {
      satellites.push_back(ids[i]);
      rtklib_sat.push_back(sats.empty() ? 0 : sats[i]);
      tle_name.push_back(names.empty() ? std::string() : names[i]);
      bool any = false;
      if (!sats.empty()) {
        // The moments its own records cover, before any extrapolation is asked of them.
        std::vector<GpsSeconds> moments;
        for (GpsSeconds t = start; t < start + kDayS; t += kRecordSearchStepS) {
          double rs[6] = {0, 0, 0, 0, 0, 0}, dts[2] = {0, 0}, var = 0.0;
          int svh = 0;
          if (satpos(to_gtime(t), to_gtime(t), sats[i], 0, nav, rs, dts, &var, &svh) && svh == 0) moments.push_back(t);
        }
        any = !moments.empty();
        valid_at.push_back(std::move(moments));
      } else {
        valid_at.emplace_back();
        for (int hour = 1; hour < 24 && !any; hour += 2) any = motion(satellites.size() - 1, start + hour * 3600.0).has_value();
      }
      if (!any) {
        satellites.pop_back();
        rtklib_sat.pop_back();
        tle_name.pop_back();
        valid_at.pop_back();
      }
    }
  }

  /// Reads the RINEX navigation file at `path` (RTKLIB's readrnx) and keeps its satellites of
  /// `systems` (all when empty). Throws std::runtime_error naming `what`.
  void read_rinex(const std::string& path, const std::string& what, const std::vector<nmea::GnssSystem>& systems) {
    const auto day = coverage_day(path);
    if (!day) throw std::runtime_error(what + ": not a RINEX navigation file with records");
    start = *day;
    nav = std::calloc(1, kNavBufferBytes);
    if (!nav) throw std::bad_alloc();
    if (readrnx(path.c_str(), 1, "", nullptr, nav, nullptr) <= 0) {
      throw std::runtime_error(what + ": RTKLIB cannot read it as RINEX navigation data");
    }
    uniqnav(nav);
    std::vector<SatelliteId> ids;
    std::vector<int> sats;
    for (int sat = 1; sat < rtk::kSatNumberLimit; ++sat) {
      int prn = 0;
      const int sys = satsys(sat, &prn);
      if (sys == 0) continue;
      const auto system = our_system(sys);
      if (!system || (!systems.empty() && std::find(systems.begin(), systems.end(), *system) == systems.end())) continue;
      ids.push_back({*system, prn});
      sats.push_back(sat);
    }
    keep_satellites_with_orbits(ids, sats, {});
  }

  /// Reads the embedded two-line elements and keeps their satellites of `systems`.
  void read_tle(const std::vector<nmea::GnssSystem>& systems);
};

Orbits::Orbits(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Orbits::~Orbits() = default;

std::shared_ptr<const Orbits> Orbits::from_rinex_nav(const std::string& path) {
  // A fleet's receivers share one file: read it once while someone holds it.
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<const Orbits>> cache;
  const std::scoped_lock lock(mutex);
  if (auto held = cache[path].lock()) return held;
  auto impl = std::make_unique<Impl>();
  impl->description = "RINEX navigation " + path;
  if (!std::ifstream(path)) throw std::runtime_error("ephemeris " + path + ": cannot be read");
  impl->read_rinex(path, "ephemeris " + path, {});
  if (impl->satellites.empty()) throw std::runtime_error("ephemeris " + path + ": no usable ephemeris in it");
  std::shared_ptr<const Orbits> orbits(new Orbits(std::move(impl)));
  cache[path] = orbits;
  return orbits;
}

std::shared_ptr<const Orbits> Orbits::embedded_default() {
  static const std::shared_ptr<const Orbits> orbits = read_embedded();
  return orbits;
}

void Orbits::Impl::read_tle(const std::vector<nmea::GnssSystem>& systems) {
  tle_start = (18597.0 - 3657.0) * kDayS;  // 2020-12-01 is day 18597 of the Unix epoch
  {
    const TextFile elements(embedded_tle_text());
    const TextFile names(embedded_tle_names_text());
    if (!tle_read(elements.path().c_str(), &tle) || !tle_name_read(names.path().c_str(), &tle)) {
      throw std::runtime_error("sky: RTKLIB cannot read the embedded two-line elements");
    }
  }
  std::vector<SatelliteId> ids;
  std::vector<std::string> names;
  std::istringstream lines{std::string(embedded_tle_names_text())};
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::string name;
    if (!(fields >> name) || name.front() == '#') continue;
    const auto id = id_of_tle_name(name);
    if (id && std::find(systems.begin(), systems.end(), id->system) != systems.end()) {
      ids.push_back(*id);
      names.push_back(name);
    }
  }
  // Sorted by system then number, like a RINEX file's.
  std::vector<std::size_t> order(ids.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto rank = [](nmea::GnssSystem s) { return rtklib_system(s); };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::pair{rank(ids[a].system), ids[a].sv_id} < std::pair{rank(ids[b].system), ids[b].sv_id};
  });
  std::vector<SatelliteId> sorted_ids;
  std::vector<std::string> sorted_names;
  for (const std::size_t i : order) {
    if (!sorted_ids.empty() && sorted_ids.back() == ids[i]) continue;  // a slot listed twice
    sorted_ids.push_back(ids[i]);
    sorted_names.push_back(names[i]);
  }
  keep_satellites_with_orbits(sorted_ids, {}, sorted_names);
}

std::shared_ptr<const Orbits> Orbits::read_embedded() {
  auto impl = std::make_unique<Impl>();
  impl->description =
      "embedded sky: merged RINEX navigation of DLR BRD400DLR, 2026-03-09 (GPS, GLONASS, Galileo, BeiDou, "
      "QZSS), and two-line elements of 2020-12-01 (SBAS, QZSS the file lacks)";
  {
    const TextFile rinex(embedded_rinex_nav_text());
    using S = nmea::GnssSystem;
    impl->read_rinex(rinex.path(), "sky: the embedded navigation file",
                     {S::gps, S::glonass, S::galileo, S::beidou, S::qzss});
  }
  // SBAS comes from the two-line elements (the thinned file keeps no SBAS records: their 6-minute
  // validity would need hundreds), and so do the QZSS satellites the file has no record of.
  // Geostationary and inclined geosynchronous satellites repeat their Earth-fixed track every
  // sidereal day, so the elements' day gives the same geometry.
  const std::vector<SatelliteId> from_rinex = impl->satellites;
  impl->read_tle({nmea::GnssSystem::qzss, nmea::GnssSystem::sbas});
  for (std::size_t i = from_rinex.size(); i < impl->satellites.size();) {
    if (std::find(from_rinex.begin(), from_rinex.end(), impl->satellites[i]) == from_rinex.end()) {
      ++i;
      continue;
    }
    impl->satellites.erase(impl->satellites.begin() + static_cast<std::ptrdiff_t>(i));
    impl->rtklib_sat.erase(impl->rtklib_sat.begin() + static_cast<std::ptrdiff_t>(i));
    impl->tle_name.erase(impl->tle_name.begin() + static_cast<std::ptrdiff_t>(i));
    impl->valid_at.erase(impl->valid_at.begin() + static_cast<std::ptrdiff_t>(i));
  }
  // One list sorted by system then number.
  std::vector<std::size_t> order(impl->satellites.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto key = [&](std::size_t i) {
    return std::pair{rtklib_system(impl->satellites[i].system), impl->satellites[i].sv_id};
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  std::vector<SatelliteId> satellites;
  std::vector<int> rtklib_sat;
  std::vector<std::string> tle_name;
  std::vector<std::vector<GpsSeconds>> valid_at;
  for (const std::size_t i : order) {
    satellites.push_back(impl->satellites[i]);
    rtklib_sat.push_back(impl->rtklib_sat[i]);
    tle_name.push_back(impl->tle_name[i]);
    valid_at.push_back(std::move(impl->valid_at[i]));
  }
  impl->satellites = std::move(satellites);
  impl->rtklib_sat = std::move(rtklib_sat);
  impl->tle_name = std::move(tle_name);
  impl->valid_at = std::move(valid_at);
  return std::shared_ptr<const Orbits>(new Orbits(std::move(impl)));
}

const std::vector<SatelliteId>& Orbits::satellites() const { return impl_->satellites; }
std::optional<EcefMotion> Orbits::motion(std::size_t index, GpsSeconds t) const { return impl_->motion(index, t); }
std::optional<Ecef> Orbits::position(std::size_t index, GpsSeconds t) const {
  const auto m = impl_->motion(index, t);
  return m ? std::optional<Ecef>(m->position) : std::nullopt;
}
GpsSeconds Orbits::coverage_start() const { return impl_->start; }
const std::string& Orbits::description() const { return impl_->description; }

GpsSeconds Orbits::map_time(GpsSeconds t) const { return same_sidereal_time(t, impl_->start); }

AzEl azimuth_elevation(const std::array<double, 3>& receiver_geodetic, const Ecef& receiver, const Ecef& satellite) {
  const double pos[3] = {receiver_geodetic[0] * kDeg, receiver_geodetic[1] * kDeg, receiver_geodetic[2]};
  const double rs[3] = {satellite.x_m, satellite.y_m, satellite.z_m};
  const double rr[3] = {receiver.x_m, receiver.y_m, receiver.z_m};
  double e[3] = {0, 0, 0}, azel[2] = {0, 0};
  geodist(rs, rr, e);
  satazel(pos, e, azel);
  double az = azel[0] / kDeg;
  if (az < 0.0) az += 360.0;
  if (az >= 360.0) az -= 360.0;
  return {az, azel[1] / kDeg};
}

Ecef to_ecef(double lat_deg, double lon_deg, double height_m) {
  const double pos[3] = {lat_deg * kDeg, lon_deg * kDeg, height_m};
  double r[3] = {0, 0, 0};
  pos2ecef(pos, r);
  return {r[0], r[1], r[2]};
}

double geoid_separation_m(double lat_deg, double lon_deg) {
  const double pos[3] = {lat_deg * kDeg, lon_deg * kDeg, 0.0};
  return geoidh(pos);
}

RtklibDops rtklib_single_clock_dops(std::span<const AzEl> satellites, double mask_deg) {
  std::vector<double> azel;
  azel.reserve(2 * satellites.size());
  for (const AzEl& s : satellites) {
    azel.push_back(s.azimuth_deg * kDeg);
    azel.push_back(s.elevation_deg * kDeg);
  }
  double dop[4] = {0, 0, 0, 0};
  dops(static_cast<int>(satellites.size()), azel.data(), mask_deg * kDeg, dop);
  return {dop[0], dop[1], dop[2], dop[3]};
}

}  // namespace gpsemu::sky
