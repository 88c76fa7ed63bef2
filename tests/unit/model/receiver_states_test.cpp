// The receiver model's states and satellite sky: cold start (acquisition, 2-D, 3-D), scheduled
// outages, fix quality noise scaling with GST, satellites/HDOP derived from the noise, a plausible
// slowly moving deterministic sky; and the options that configure them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "emulator/config/config.hpp"
#include "emulator/model/accuracy.hpp"
#include "emulator/model/receiver.hpp"
#include "emulator/model/receiver_models.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/sources/sim.hpp"
#include "nmea/parse.hpp"
#include "nmea/sentences.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu {
namespace {
namespace receiver_states_test {

using namespace std::chrono;

const UtcNs kStart = parse_iso8601_utc("2024-05-01T12:00:00Z");
const LocalFrame kFrame({43.0725, -89.4125, 260.0});
const sources::Truth kAtOrigin{};

std::unique_ptr<noise::NoiseModel> noise_model(noise::Model model, double sigma_m = 1.0) {
  noise::NoiseConfig c;
  c.model = model;
  for (auto& axis : c.gaussian) axis.sigma_m = sigma_m;
  return noise::make_noise_model(c, 7);
}

UtcNs at(double seconds) { return kStart + nanoseconds{std::llround(seconds * 1e9)}; }

/// The first sentence of several (GSA: one per system).
std::string first_line(const std::string& text) { return text.substr(0, text.find('\n') + 1); }

int used_flags(const nmea::Fix& fix) {
  int n = 0;
  for (int i = 0; i < fix.satellites_in_view; ++i) n += fix.satellites[static_cast<std::size_t>(i)].used;
  return n;
}

TEST(ReceiverGeometry, WorstCaseCountsFollowTheModelsSystems) {
  ReceiverOptions o;  // generic = M8N: GPS 14 + GLONASS 12 + QZSS 5 + SBAS 4
  EXPECT_EQ(resolve_geometry(o).satellites_in_view, 35);
  o.tracking = facts_of(ReceiverModel::ublox_f9p).tracking;  // six systems, two signals: capped
  EXPECT_EQ(resolve_geometry(o).satellites_in_view, static_cast<int>(nmea::max_satellites));
  o.satellites_used = 10;
  EXPECT_EQ(resolve_geometry(o).satellites_used, 10);
}

TEST(ReceiverGeometry, NoiseSigmaEstimateMatchesTheModel) {
  noise::NoiseConfig c;
  c.model = noise::Model::gaussian;
  c.gaussian = {noise::GaussianAxis{0.0, 1.0}, noise::GaussianAxis{0.0, 2.0}, noise::GaussianAxis{0.0, 3.0}};
  const Enu s = estimate_noise_sigma_m(c, 3);
  EXPECT_NEAR(s.east_m, 1.0, 0.03);
  EXPECT_NEAR(s.north_m, 2.0, 0.06);
  EXPECT_NEAR(s.up_m, 3.0, 0.09);
  c.model = noise::Model::cgrw;
  c.cgrw = noise::cgrw_preset(1.0);
  const Enu w = estimate_noise_sigma_m(c, 3);  // the preset: about 0.25 x the width
  EXPECT_NEAR(w.east_m, 0.25, 0.08);
  EXPECT_NEAR(w.north_m, 0.25, 0.08);
  c.model = noise::Model::none;
  EXPECT_EQ(estimate_noise_sigma_m(c, 3).east_m, 0.0);
}

TEST(ReceiverStates, ColdStartAcquiresThenTwoDThenThreeD) {
  ReceiverOptions o;
  o.noise_sigma_m = {0.25, 0.25, 0.375};
  o.cold_start_s = 20.0;
  o.cold_start_2d_s = 5.0;
  Receiver rx(kFrame, o, noise_model(noise::Model::none), kStart);
  const Geometry g = rx.geometry();
  int last_in_view = 0;
  const nmea::FormatOptions fmt;
  for (int s = 0; s < 40; ++s) {
    const nmea::Fix fix = rx.fix_at(at(s), kAtOrigin);
    EXPECT_EQ(phase_at(o, s), s < 20 ? ReceiverPhase::acquiring : s < 25 ? ReceiverPhase::two_d : ReceiverPhase::three_d);
    if (s < 20) {
      EXPECT_FALSE(fix.has_fix()) << s;
      EXPECT_EQ(fix.time_valid, fix.satellites_in_view > 0) << "the time comes with the first satellite";
      if (s == 0) {
        EXPECT_FALSE(fix.time_valid);
      }
      EXPECT_GE(fix.satellites_in_view, last_in_view) << "satellites are acquired one by one";
      EXPECT_LE(fix.satellites_in_view, g.satellites_in_view);
      EXPECT_EQ(used_flags(fix), 0);
      last_in_view = fix.satellites_in_view;
      const auto gga = nmea::parse_gga(*nmea::parse_sentence(nmea::format_gga(fix, fmt)));
      EXPECT_EQ(gga->quality, nmea::FixQuality::none);
    } else if (s < 25) {
      ASSERT_TRUE(fix.has_fix()) << s;
      EXPECT_EQ(fix.dimension, nmea::FixDimension::two_d);
      EXPECT_EQ(fix.satellites_used, kTwoDSatellites);
      EXPECT_EQ(used_flags(fix), kTwoDSatellites);
      EXPECT_GE(fix.hdop, g.hdop);
      const auto gga = nmea::parse_gga(*nmea::parse_sentence(nmea::format_gga(fix, fmt)));
      EXPECT_FALSE(gga->alt_msl_m.has_value()) << "a 2-D fix has no altitude";
      EXPECT_EQ(nmea::parse_sentence(first_line(nmea::format_gsa(fix, fmt)))->fields[1], "2");
    } else {
      ASSERT_TRUE(fix.has_fix()) << s;
      EXPECT_EQ(fix.dimension, nmea::FixDimension::three_d);
      EXPECT_GE(fix.satellites_used, 6);
      EXPECT_EQ(used_flags(fix), fix.satellites_used);
      EXPECT_NEAR(fix.satellites_in_view, g.satellites_in_view, 1) << "the sky at the first epoch";
      EXPECT_EQ(nmea::parse_sentence(first_line(nmea::format_gsa(fix, fmt)))->fields[1], "3");
    }
  }
  EXPECT_GT(last_in_view, g.satellites_in_view / 2);
  EXPECT_LT(last_in_view, g.satellites_in_view + 1);
}

TEST(ReceiverStates, OutageEmptiesTheSkyAndTheFixReturnsAfterIt) {
  ReceiverOptions o;
  o.outages = {{10.0, 5.0}, {30.0, 0.5}};
  Receiver rx(kFrame, o, noise_model(noise::Model::none), kStart);
  for (double s = 0.0; s < 40.0; s += 0.1) {
    const nmea::Fix fix = rx.fix_at(at(s), kAtOrigin);
    const bool out = (s >= 10.0 - 1e-9 && s < 15.0 - 1e-9) || (s >= 30.0 - 1e-9 && s < 30.5 - 1e-9);
    EXPECT_EQ(fix.has_fix(), !out) << s;
    if (out) {
      EXPECT_EQ(fix.satellites_in_view, 0) << s;
      EXPECT_EQ(nmea::format_gsv(fix, {}), "$GPGSV,1,1,00,1*64\r\n");
      EXPECT_EQ(nmea::parse_sentence(nmea::format_rmc(fix, {}))->fields[1], "V");
    } else {
      EXPECT_EQ(fix.dimension, nmea::FixDimension::three_d) << s;
    }
  }
}

TEST(ReceiverStates, StalePoseIsNoFixWithSatellitesStillTracked) {
  Receiver rx(kFrame, {}, noise_model(noise::Model::none), kStart);
  const nmea::Fix fix = rx.fix_at(at(1.0), std::nullopt);
  EXPECT_FALSE(fix.has_fix());
  EXPECT_EQ(fix.satellites_in_view, rx.geometry().satellites_in_view);
  EXPECT_EQ(used_flags(fix), 0);
}

TEST(ReceiverStates, FixQualityShrinksTheNoiseAndGstSaysSo) {
  struct Case {
    nmea::FixQuality quality;
    double scale;
  };
  for (const Case c : {Case{nmea::FixQuality::gps, 1.0}, Case{nmea::FixQuality::dgps, 0.4},
                       Case{nmea::FixQuality::rtk_float, 0.1}, Case{nmea::FixQuality::rtk_fixed, 0.01}}) {
    EXPECT_EQ(noise_scale(c.quality), c.scale);
    ReceiverOptions o;
    o.quality = c.quality;
    o.noise_sigma_m = {2.0, 2.0, 2.0};
    Receiver rx(kFrame, o, noise_model(noise::Model::gaussian, 2.0), kStart);
    double sum_sq_east = 0.0, sum_sq_north = 0.0;
    constexpr int n = 2000;
    nmea::Fix fix;
    for (int k = 0; k < n; ++k) {
      fix = rx.fix_at(at(k), kAtOrigin);
      ASSERT_EQ(fix.quality, c.quality);
      const Enu e = kFrame.to_enu({fix.lat_deg, fix.lon_deg, fix.alt_msl_m});
      sum_sq_east += e.east_m * e.east_m;
      sum_sq_north += e.north_m * e.north_m;
    }
    EXPECT_NEAR(std::sqrt(sum_sq_east / n), 2.0 * c.scale, 0.1 * c.scale);
    EXPECT_NEAR(std::sqrt(sum_sq_north / n), 2.0 * c.scale, 0.1 * c.scale);
    // Reported accuracy: the applied error's sigma (the model's x the quality's scale), never
    // below the floor; GST's range RMS: the model's UERE x the scale.
    const double floor_m = sky::accuracy_floor_m(c.quality);
    EXPECT_DOUBLE_EQ(fix.sigma_lat_m, std::max(floor_m, 2.0 * c.scale));
    EXPECT_DOUBLE_EQ(fix.sigma_lon_m, fix.sigma_lat_m);
    EXPECT_DOUBLE_EQ(fix.sigma_alt_m, std::max(1.5 * floor_m, 2.0 * c.scale));
    EXPECT_DOUBLE_EQ(fix.range_rms_m, std::max(floor_m, o.tracking.uere_m * c.scale));
    EXPECT_GT(fix.sigma_lat_m, 0.0);
    EXPECT_GT(fix.hdop, 0.3);
    EXPECT_LT(fix.hdop, 2.0);
  }
}

TEST(ReceiverStates, WithoutNoiseTheAccuracyIsDopTimesUere) {
  ReceiverOptions o;  // noise_sigma_m 0: --noise none
  Receiver rx(kFrame, o, noise_model(noise::Model::none), kStart);
  const nmea::Fix fix = rx.fix_at(at(1.0), kAtOrigin);
  ASSERT_TRUE(fix.has_fix());
  EXPECT_DOUBLE_EQ(fix.sigma_lat_m, std::max(sky::accuracy_floor_m(o.quality), fix.hdop * o.tracking.uere_m / std::sqrt(2.0)));
  EXPECT_DOUBLE_EQ(fix.sigma_alt_m, std::max(1.5 * sky::accuracy_floor_m(o.quality), fix.vdop * o.tracking.uere_m));
}

TEST(ReceiverStates, AccuracyIsNeverZeroEvenWithoutNoise) {
  for (const auto q : {nmea::FixQuality::gps, nmea::FixQuality::rtk_fixed}) {
    ReceiverOptions o;
    o.quality = q;
    Receiver rx(kFrame, o, noise_model(noise::Model::none), kStart);
    const nmea::Fix fix = rx.fix_at(at(1.0), kAtOrigin);
    ASSERT_TRUE(fix.has_fix());
    EXPECT_GE(fix.sigma_lat_m, sky::accuracy_floor_m(q));
    EXPECT_GE(fix.sigma_alt_m, sky::accuracy_floor_m(q));
    EXPECT_GT(fix.range_rms_m, 0.0);
  }
}

TEST(ReceiverStates, NoiseScalesWithDopOnlyWhenAsked) {
  ReceiverOptions o;
  o.sky_mask = parse_sky_mask("urban-canyon");  // a poorer geometry: HDOP well above 1
  Receiver plain(kFrame, o, noise_model(noise::Model::gaussian, 1.0), kStart);
  o.noise_scales_with_dop = true;
  Receiver scaled(kFrame, o, noise_model(noise::Model::gaussian, 1.0), kStart);
  const nmea::Fix a = plain.fix_at(at(3.0), kAtOrigin), b = scaled.fix_at(at(3.0), kAtOrigin);
  ASSERT_TRUE(a.has_fix() && b.has_fix());
  const Enu ea = kFrame.to_enu({a.lat_deg, a.lon_deg, a.alt_msl_m}), eb = kFrame.to_enu({b.lat_deg, b.lon_deg, b.alt_msl_m});
  EXPECT_NEAR(eb.east_m, ea.east_m * a.hdop / kReferenceHdop, 1e-6);
  EXPECT_NEAR(eb.up_m, ea.up_m * a.vdop / kReferenceVdop, 1e-6);
}

TEST(ReceiverStates, GeoidSeparationIsTheEgm96GeoidUnlessGiven) {
  Receiver rx(kFrame, {}, noise_model(noise::Model::none), kStart);
  // EGM96 at Madison, Wisconsin: about -34 m (NGA's calculator: -33.9 m).
  EXPECT_NEAR(rx.fix_at(at(1.0), kAtOrigin).geoid_sep_m, -33.9, 1.5);
  ReceiverOptions o;
  o.geoid_sep_m = 12.5;
  Receiver given(kFrame, o, noise_model(noise::Model::none), kStart);
  EXPECT_EQ(given.fix_at(at(1.0), kAtOrigin).geoid_sep_m, 12.5);
}

TEST(Sky, SatellitesArePlausibleConsistentAndMoveSlowly) {
  ReceiverOptions o;
  Receiver rx(kFrame, o, noise_model(noise::Model::none), kStart);
  nmea::Fix previous;
  for (int s = 0; s < 600; ++s) {
    const nmea::Fix fix = rx.fix_at(at(s), kAtOrigin);
    ASSERT_GE(fix.satellites_in_view, 12);
    ASSERT_EQ(used_flags(fix), fix.satellites_used);
    for (int i = 0; i < fix.satellites_in_view; ++i) {
      const auto& sat = fix.satellites[static_cast<std::size_t>(i)];
      ASSERT_NE(sat.system, nmea::GnssSystem::galileo) << "an M8N tracks GPS, GLONASS, QZSS and SBAS";
      ASSERT_NE(sat.system, nmea::GnssSystem::beidou);
      ASSERT_GE(sat.elevation_deg, 0);
      ASSERT_LE(sat.elevation_deg, 90);
      ASSERT_GE(sat.azimuth_deg, 0);
      ASSERT_LT(sat.azimuth_deg, 360);
      ASSERT_TRUE(sat.snr_dbhz.has_value());
      if (sat.used) {
        ASSERT_GE(sat.elevation_deg, 5) << "used only above the elevation mask";
      }
      if (s > 0 && previous.satellites_in_view == fix.satellites_in_view) {
        const auto& before = previous.satellites[static_cast<std::size_t>(i)];
        if (before.sv_id != sat.sv_id) continue;
        ASSERT_LE(std::abs(sat.elevation_deg - before.elevation_deg), 1) << s;
        const int daz = std::abs(sat.azimuth_deg - before.azimuth_deg);
        ASSERT_LE(std::min(daz, 360 - daz), 2) << s;
      }
    }
    previous = fix;
  }
}

TEST(Sky, SameSeedSameSkyOtherSeedOtherSky) {
  auto sky_text = [](std::uint64_t seed) {
    ReceiverOptions o;
    o.sky_seed = seed;
    Receiver rx(kFrame, o, noise_model(noise::Model::none), kStart);
    return nmea::format_gsv(rx.fix_at(at(100.0), kAtOrigin), {});
  };
  EXPECT_EQ(sky_text(5), sky_text(5));
  EXPECT_NE(sky_text(5), sky_text(6));
}

// Options

Config config_of(const RawOptions& cli) { return build_config(std::nullopt, cli); }

nmea::LineBudget line_budget_of(const RawOptions& cli) {
  const Config c = config_of(cli);
  return line_budget(c.receiver(), c.timeline.rate_hz);
}

std::string error_of(const RawOptions& cli) {
  try {
    (void)config_of(cli);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ReceiverOptionsConfig, SentencesAreWrittenInReceiverOrderWhateverTheGivenOrder) {
  EXPECT_EQ(config_of({}).receiver().format.sentences, nmea::SentenceSet::ublox_default());
  const Config c = config_of({{"sentences", {"zda, gga,RMC"}}});
  std::string order;
  c.receiver().format.sentences.for_each([&](nmea::SentenceType t) { order += nmea::sentence_name(t); });
  EXPECT_EQ(order, "RMCGGAZDA");
  EXPECT_NE(error_of({{"sentences", {"GGA,TXT"}}}).find("--sentences: sentences: unknown sentence 'TXT'"), std::string::npos)
      << error_of({{"sentences", {"GGA,TXT"}}});
  EXPECT_NE(error_of({{"sentences", {","}}}).find("unknown sentence ''"), std::string::npos);
}

TEST(ReceiverOptionsConfig, FixQualityColdStartAndRepeatableOutages) {
  const Config c = config_of({{"fix-quality", {"rtk-fixed"}},
                              {"cold-start", {"30"}},
                              {"outage", {"60+5", "120.5+0.5"}}});
  EXPECT_EQ(c.receiver().model.quality, nmea::FixQuality::rtk_fixed);
  EXPECT_EQ(c.receiver().model.cold_start_s, 30.0);
  EXPECT_EQ(c.receiver().model.cold_start_2d_s, 2.0);
  ASSERT_EQ(c.receiver().model.outages.size(), 2u);
  EXPECT_EQ(c.receiver().model.outages[1].start_s, 120.5);
  EXPECT_EQ(c.receiver().model.outages[1].duration_s, 0.5);
  EXPECT_EQ(config_of({{"cold-start", {"0,4"}}}).receiver().model.cold_start_2d_s, 4.0);
  EXPECT_EQ(config_of({}).receiver().model.cold_start_2d_s, 0.0);
  EXPECT_NE(error_of({{"fix-quality", {"ppp"}}}).find("--fix-quality"), std::string::npos);
  EXPECT_NE(error_of({{"outage", {"60"}}}).find("START+DURATION"), std::string::npos);
  EXPECT_NE(error_of({{"outage", {"60+0"}}}).find("DURATION must be > 0"), std::string::npos);
  EXPECT_NE(error_of({{"outage", {"-5+3"}}}).find("outage START"), std::string::npos) << error_of({{"outage", {"-5+3"}}});
  EXPECT_NE(error_of({{"cold-start", {"-1"}}}).find("--cold-start"), std::string::npos);
}

TEST(ReceiverOptionsConfig, OutagesAndSentencesFromAConfigFileArray) {
  const auto path = test::scratch_root() / ("gpsemu_states_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(path) << "outage = [\"10+2\", \"20+3\"]\nsentences = [\"GGA\", \"RMC\", \"GST\"]\nfix-quality = \"dgps\"\n";
  const Config c = build_config(path.string(), {});
  std::filesystem::remove(path);
  ASSERT_EQ(c.receiver().model.outages.size(), 2u);
  EXPECT_EQ(c.receiver().model.outages[0].start_s, 10.0);
  EXPECT_EQ(c.receiver().model.outages[1].duration_s, 3.0);
  EXPECT_TRUE(c.receiver().format.sentences.contains(nmea::SentenceType::gst));
  EXPECT_FALSE(c.receiver().format.sentences.contains(nmea::SentenceType::gsv));
  EXPECT_EQ(c.receiver().model.quality, nmea::FixQuality::dgps);
}

TEST(ReceiverOptionsConfig, LineBudgetOfTheConfiguredRun) {
  // Default: u-blox set, an M8N's worst case of 35 in view by system (GPS 14 with SBAS 4 in the
  // GP groups, GLONASS 12, QZSS 5): four GSV groups and GSAs; 10 Hz needs 230400 baud.
  const nmea::LineBudget b10 = line_budget_of({{"rate", {"10"}}});
  EXPECT_GT(b10.bytes_per_epoch, 1152u);  // more than 115200 baud carries in 100 ms
  EXPECT_EQ(nmea::smallest_standard_baud(b10), 230400);
  EXPECT_FALSE(b10.fits(115200));
  const nmea::LineBudget gga_rmc = line_budget_of({{"rate", {"10"}}, {"sentences", {"GGA,RMC"}}});
  EXPECT_EQ(gga_rmc.bytes_per_epoch, 168u);  // GGA's widest altitude -12345.6 m, RTK age and station
  EXPECT_EQ(nmea::smallest_standard_baud(gga_rmc), 19200);
}

}  // namespace receiver_states_test
}  // namespace
}  // namespace gpsemu
