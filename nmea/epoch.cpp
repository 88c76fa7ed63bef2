// One epoch's sentences in receiver order (table-driven dispatch by SentenceType).
#include <array>
#include <string>

#include "nmea/epoch_fields.hpp"
#include "nmea/sentences.hpp"

namespace gpsemu::nmea {
namespace {

using Formatter = std::string (*)(const Fix&, const FormatOptions&);

// Indexed by SentenceType (output order).
constexpr std::array<Formatter, all_sentence_types.size()> formatters = {
    format_rmc, format_vtg, format_gga, format_gsa, format_gsv, format_gll, format_gst, format_zda};

}  // namespace

std::string format_sentences(SentenceType type, const Fix& fix, const FormatOptions& options) {
  return formatters[static_cast<std::size_t>(type)](fix, options);
}

void append_epoch(const Fix& fix, const FormatOptions& options, std::string& out) {
  // GGA and RMC share the time and position fields: formatted once, written straight into `out`.
  const bool with_gga = options.sentences.contains(SentenceType::gga);
  const bool with_rmc = options.sentences.contains(SentenceType::rmc);
  const EpochFields fields = with_gga || with_rmc ? epoch_fields(fix, options, with_rmc) : EpochFields{};
  options.sentences.for_each([&](SentenceType type) {
    switch (type) {
      case SentenceType::gga: append_gga(fix, options, fields, out); break;
      case SentenceType::rmc: append_rmc(fix, options, fields, out); break;
      case SentenceType::gsa: append_gsa(fix, options, out); break;
      case SentenceType::gsv: append_gsv(fix, options, out); break;
      default: out += format_sentences(type, fix, options); break;
    }
  });
}

}  // namespace gpsemu::nmea
