// The embedded default sky's data (data/sky/ compiled into the program by CMake, so a binary
// needs no data directory): merged multi-GNSS navigation data of the whole of 2026-03-09 (DLR's
// BRD400DLR of IGS and CONGO stations, as RINEX 3.05, thinned), RTKLIB's GNSS two-line elements
// of 2020-12-01 and its satellite name table.
// See data/sky/README.md.
#pragma once

#include <string_view>

namespace gpsemu::sky {

[[nodiscard]] std::string_view embedded_rinex_nav_text();   ///< data/sky/BRD400DLR_S_20260680000_01D_MN-thinned.rnx
[[nodiscard]] std::string_view embedded_tle_text();        ///< data/sky/gnss-tle-2020-12-01.txt
[[nodiscard]] std::string_view embedded_tle_names_text();  ///< data/sky/gnss-satno.txt

}  // namespace gpsemu::sky
