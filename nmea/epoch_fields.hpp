// The fields several sentences of one epoch share (time of day, date, latitude, longitude),
// formatted once per epoch, and the GGA and RMC writers that take them: the path append_epoch
// takes a million times a second in --fast mode, with no allocation and no formatting twice.
// Internal to nmea/ (format_gga, format_rmc and append_epoch in sentences.hpp are the interface).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>

#include "nmea/fields.hpp"
#include "nmea/fix.hpp"

namespace gpsemu::nmea {

/// A field of at most 16 characters, copied into a sentence with one fixed-size move.
struct FieldText {
  std::array<char, 16> chars{};
  std::uint8_t size = 0;
};
static_assert(fields::max_coordinate_chars <= 16);

/// Writes `field` at `p` (copies all 16 bytes: the buffer needs 16 writable bytes at `p`).
inline char* put_field(char* p, const FieldText& field) {
  std::memcpy(p, field.chars.data(), field.chars.size());
  return p + field.size;
}

/// One epoch's shared fields. Latitude and longitude are set only for a fix, the date only when
/// asked for.
struct EpochFields {
  FieldText time;       ///< "hhmmss.ss" (fields::format_time_of_day)
  FieldText date;       ///< "ddmmyy"
  FieldText latitude;   ///< "ddmm.mmmmm,N" (value and hemisphere), "," when empty
  FieldText longitude;  ///< "dddmm.mmmmm,E", "," when empty
};

[[nodiscard]] EpochFields epoch_fields(const Fix& fix, const FormatOptions& options, bool with_date);

/// Appends the GGA / RMC sentence of `fix` (as format_gga / format_rmc) to `out`, from `fields`
/// (from epoch_fields(fix, options, ...); RMC needs the date).
void append_gga(const Fix& fix, const FormatOptions& options, const EpochFields& fields, std::string& out);
void append_rmc(const Fix& fix, const FormatOptions& options, const EpochFields& fields, std::string& out);
/// Appends the VTG / GLL sentence of `fix` (as format_vtg / format_gll); GLL from `fields`.
void append_vtg(const Fix& fix, const FormatOptions& options, std::string& out);
void append_gll(const Fix& fix, const FormatOptions& options, const EpochFields& fields, std::string& out);

}  // namespace gpsemu::nmea
