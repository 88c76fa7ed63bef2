// Receiver profiles (--profile NAME, `profile = "NAME"`): the catalogue compiled in, what a profile
// sets, and that the config file and the command line override it.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "emulator/config/config.hpp"
#include "emulator/config/profiles.hpp"
#include "emulator/ubx/model.hpp"
#include "tests/support/config_files.hpp"

namespace gpsemu {
namespace {
namespace profiles_test {

std::string write_temp(const std::string& name, const std::string& text) {
  return test::write_temp("gpsemu_profile_", name, text);
}

// Issue 34: at least a ZED-F9P, an M8-class, an M9N/M10-class, a Quectel L76K, a Telit, a
// SiRF/SkyTraq-class receiver and an RTK-fixed rover, each with its [profile] description.
TEST(Profiles, TheCatalogueHoldsEveryReceiverClassWithItsDescription) {
  std::set<std::string> names;
  for (const profiles::Profile& p : profiles::catalogue()) {
    const profiles::Summary s = profiles::summary(p);
    EXPECT_EQ(s.name, p.name);
    EXPECT_FALSE(s.receiver.empty()) << p.name;
    EXPECT_NE(s.licence.find("BSD-2-Clause"), std::string::npos) << p.name << ": " << s.licence;
    EXPECT_FALSE(s.recorded.empty()) << p.name;
    EXPECT_NE(s.conditions.find("static"), std::string::npos) << p.name << ": " << s.conditions;
    EXPECT_GT(s.rate_hz, 0.0) << p.name;
    EXPECT_GT(s.sigma_m[0], 0.0) << p.name;
    EXPECT_GT(s.sigma_m[1], 0.0) << p.name;
    EXPECT_EQ(s.goal_checks, 6) << p.name;
    EXPECT_EQ(s.goal_reached + static_cast<int>(s.goal_misses.size()), s.goal_checks) << p.name;
    names.insert(s.name);
  }
  for (const char* wanted : {"ublox-zed-f9p", "ublox-max-m8q", "ublox-neo-m9n", "quectel-l76k", "telit-he910",
                             "sirfstar-v", "skytraq-s2525f8", "trimble-rtk-fixed"}) {
    EXPECT_TRUE(names.count(wanted)) << wanted << " is not in the catalogue";
  }
}

// Every profile loads, and sets what its description says: the rate, the noise model, the receiver model.
TEST(Profiles, EachProfileLoadsAndSetsItsRateNoiseAndReceiverModel) {
  for (const profiles::Profile& p : profiles::catalogue()) {
    const profiles::Summary s = profiles::summary(p);
    const Config c = build_config(std::nullopt, {{"profile", {std::string(p.name)}}});
    EXPECT_DOUBLE_EQ(c.timeline.rate_hz, s.rate_hz) << p.name;
    EXPECT_EQ(noise::to_string(c.receiver().noise.model), s.noise) << p.name;
    EXPECT_EQ(ubx::model_info(c.receiver().receiver_model).name, s.model.empty() ? "generic" : s.model) << p.name;
    // A profile is a receiver, not a place: the origin stays the default.
    EXPECT_DOUBLE_EQ(c.receiver().origin.lat_deg, 43.0725) << p.name;
  }
  const Config f9p = build_config(std::nullopt, {{"profile", {"ublox-zed-f9p"}}});
  EXPECT_EQ(f9p.receiver().receiver_model, ReceiverModel::ublox_f9p);
  EXPECT_EQ(f9p.process.profile, std::optional<std::string>("ublox-zed-f9p"));
  EXPECT_FALSE(build_config(std::nullopt, {}).process.profile.has_value());
}

// A profile's own text is a config file: loaded with --config it is the same as --profile.
TEST(Profiles, AProfilesTextLoadsAsAConfigFileWithItsDescriptionSkipped) {
  const profiles::Profile& p = profiles::get("ublox-zed-f9p");
  const Config by_name = build_config(std::nullopt, {{"profile", {"ublox-zed-f9p"}}});
  const Config by_file = build_config(write_temp("f9p.toml", std::string(p.text)), {});
  EXPECT_EQ(by_file.receiver().noise.model, by_name.receiver().noise.model);
  EXPECT_EQ(by_file.receiver().receiver_model, by_name.receiver().receiver_model);
  EXPECT_EQ(by_file.receiver().format.minute_decimals, by_name.receiver().format.minute_decimals);
  EXPECT_DOUBLE_EQ(by_file.receiver().noise.composite.axes[0].jitter_sigma_m,
                   by_name.receiver().noise.composite.axes[0].jitter_sigma_m);
}

// Explicit options override the profile: the file's keys, then the command line's.
TEST(Profiles, TheConfigFileAndTheCommandLineOverrideTheProfile) {
  const Config flags = build_config(std::nullopt, {{"profile", {"ublox-zed-f9p"}}, {"rate", {"5"}}, {"noise", {"gaussian"}},
                                                   {"receiver", {"generic"}}});
  EXPECT_DOUBLE_EQ(flags.timeline.rate_hz, 5.0);
  EXPECT_EQ(flags.receiver().noise.model, noise::Model::gaussian);
  EXPECT_EQ(flags.receiver().receiver_model, ReceiverModel::generic);

  const auto file = write_temp("with-profile.toml", "profile = \"telit-he910\"\nrate = 2\n");
  const Config from_file = build_config(file, {});
  EXPECT_DOUBLE_EQ(from_file.timeline.rate_hz, 2.0);
  EXPECT_EQ(noise::to_string(from_file.receiver().noise.model), profiles::summary(profiles::get("telit-he910")).noise);
  // --profile on the command line replaces the file's profile; the file's own keys still apply.
  const Config both = build_config(file, {{"profile", {"ublox-zed-f9p"}}});
  EXPECT_EQ(both.receiver().receiver_model, ReceiverModel::ublox_f9p);
  EXPECT_DOUBLE_EQ(both.timeline.rate_hz, 2.0);
}

TEST(Profiles, AnUnknownProfileIsNamedWithTheProfilesThereAre) {
  std::string e = test::config_error_of(std::nullopt, {{"profile", {"ublox-zed-f10"}}});
  EXPECT_NE(e.find("--profile: unknown profile 'ublox-zed-f10'"), std::string::npos) << e;
  EXPECT_NE(e.find("ublox-zed-f9p"), std::string::npos) << e;
  const auto file = write_temp("bad-profile.toml", "# a comment\nprofile = \"sirf\"\n");
  e = test::config_error_of(file, {});
  EXPECT_NE(e.find(":2: key 'profile': unknown profile 'sirf'"), std::string::npos) << e;
  const auto table = write_temp("table-profile.toml", "[[receiver]]\nprofile = \"telit-he910\"\n");
  e = test::config_error_of(table, {});
  EXPECT_NE(e.find("key 'profile' cannot be set in a [[receiver]] table"), std::string::npos) << e;
}

}  // namespace profiles_test
}  // namespace
}  // namespace gpsemu
