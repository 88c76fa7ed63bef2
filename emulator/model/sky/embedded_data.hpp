// The embedded default sky's data (data/sky/ compiled into the program by CMake, so a binary
// needs no data directory): a day of multi-GNSS RINEX 3 navigation data (IGS station ELKO,
// 2018-07-29), RTKLIB's GNSS two-line elements of 2020-12-01 and its satellite name table. See
// data/sky/README.md.
#pragma once

#include <string_view>

namespace gpsemu::sky {

[[nodiscard]] std::string_view embedded_rinex_nav_text();   ///< data/sky/ELKO00USA_R_20182100000_01D_MN-thinned.rnx
[[nodiscard]] std::string_view embedded_tle_text();        ///< data/sky/gnss-tle-2020-12-01.txt
[[nodiscard]] std::string_view embedded_tle_names_text();  ///< data/sky/gnss-satno.txt

}  // namespace gpsemu::sky
