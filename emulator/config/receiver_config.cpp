#include "emulator/config/receiver_config.hpp"

namespace gpsemu {

ReceiverOptions receiver_options(const Config& config) {
  ReceiverOptions options = config.receiver;
  options.noise_sigma_m = estimate_noise_sigma_m(config.noise, config.seed);
  options.sky_seed = config.seed;
  options.satellite_details =
      config.format.sentences.contains(nmea::SentenceType::gsa) || config.format.sentences.contains(nmea::SentenceType::gsv);
  return options;
}

nmea::LineBudget line_budget(const Config& config) {
  const Geometry g = resolve_geometry(receiver_options(config));
  return nmea::line_budget(config.format, g.satellites_in_view, g.satellites_used, config.rate_hz);
}

}  // namespace gpsemu
