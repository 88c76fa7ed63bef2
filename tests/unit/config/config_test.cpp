// The option table, config file loading and their error messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "emulator/config/config.hpp"
#include "emulator/model/sky/orbits.hpp"
#include "tests/support/config_files.hpp"
#include "tests/support/output_texts.hpp"

namespace gpsemu {
namespace {
namespace config_test {

std::string write_temp(const std::string& name, const std::string& text) {
  return test::write_temp("gpsemu_cfg_", name, text);
}

std::string error_of(const std::optional<std::string>& file, const RawOptions& cli) { return test::config_error_of(file, cli); }

TEST(Config, DefaultsAreTheEmbeddedScenario) {
  const Config c = build_config(std::nullopt, {});
  EXPECT_EQ(to_string(c.receiver().source), "sim:stationary");
  EXPECT_DOUBLE_EQ(c.timeline.rate_hz, 1.0);
  EXPECT_DOUBLE_EQ(c.receiver().origin.lat_deg, 43.0725);
  EXPECT_DOUBLE_EQ(c.receiver().origin.lon_deg, -89.4125);
  EXPECT_EQ(c.receiver().noise.model, noise::Model::cgrw);
  EXPECT_EQ(test::output_texts(c.receiver().outputs), std::vector<std::string>{"pty:/tmp/gpsemu"});
}

// The sky's orbits come with the configuration, before a run chooses its first epoch: the
// embedded sky takes 50-90 ms to parse, and read by the first receiver's set-up it had made that
// epoch late (written 20-80 ms after its deadline at 10 Hz; skipped under the sanitizers).
TEST(Config, TheEmbeddedSkysOrbitsAreReadWithTheConfiguration) {
  const Config c = build_config(std::nullopt, {{"receivers", {"2"}}, {"output", {"udp:127.0.0.1:{20000+i}"}}});
  ASSERT_EQ(c.receivers.size(), 2u);
  for (const ReceiverSettings& r : c.receivers) {
    ASSERT_NE(r.model.orbits, nullptr);
    EXPECT_EQ(r.model.orbits.get(), sky::Orbits::embedded_default().get());
    EXPECT_FALSE(r.model.orbits->satellites().empty());
  }
}

TEST(Config, CommandLineOverridesConfigFile) {
  const auto file = write_temp("a.toml", "rate = 5\nlatency = 0.02\noutput = [\"stdout\", \"file:/tmp/x\"]\n");
  const Config c = build_config(file, {{"rate", {"10"}}});
  EXPECT_DOUBLE_EQ(c.timeline.rate_hz, 10.0);
  EXPECT_DOUBLE_EQ(c.timeline.latency_s, 0.02);
  EXPECT_EQ(test::output_texts(c.receiver().outputs), (std::vector<std::string>{"stdout", "file:/tmp/x"}));
}

TEST(Config, FileErrorsNameFileLineAndKey) {
  const auto unknown = write_temp("b.toml", "rate = 5\n\nratte = 3\n");
  EXPECT_NE(error_of(unknown, {}).find(":3: unknown key 'ratte'"), std::string::npos) << error_of(unknown, {});
  const auto bad_value = write_temp("c.toml", "# comment\nrate = 500\n");
  const std::string e = error_of(bad_value, {});
  EXPECT_NE(e.find(":2: key 'rate'"), std::string::npos) << e;
  EXPECT_NE(e.find("from 0.1 to 50"), std::string::npos) << e;
  const auto syntax = write_temp("d.toml", "rate = \n");
  EXPECT_NE(error_of(syntax, {}).find(":1:"), std::string::npos) << error_of(syntax, {});
}

// Issue 22, point 11: `output = 5` was silently replaced by --output; a number for a text option
// is refused whether the command line gives the option or not, in a [[receiver]] table too.
TEST(Config, ANumberForATextOptionIsRefusedEvenWhenTheCommandLineGivesIt) {
  const auto file = write_temp("number.toml", "rate = 5\noutput = 5\n");
  for (const RawOptions& cli : {RawOptions{}, RawOptions{{"output", {"stdout"}}}}) {
    const std::string e = error_of(file, cli);
    EXPECT_NE(e.find(":2: key 'output': expected a string (SPEC), got an integer (5)"), std::string::npos) << e;
  }
  const auto list = write_temp("list.toml", "output = [\"stdout\", true]\n");
  EXPECT_NE(error_of(list, {}).find("expected a string (SPEC), got a boolean"), std::string::npos) << error_of(list, {});
  const auto table = write_temp("table.toml", "[[receiver]]\noutput = 7.5\n");
  EXPECT_NE(error_of(table, {}).find("key 'output': expected a string (SPEC), got a number"), std::string::npos)
      << error_of(table, {});
  // A number where a number belongs is still fine, and a string for a text option.
  EXPECT_NO_THROW((void)build_config(write_temp("ok.toml", "rate = 5\noutput = \"stdout\"\n"), {}));
}

TEST(Config, FlagErrorsNameTheFlagAndTheAcceptedValues) {
  EXPECT_NE(error_of(std::nullopt, {{"noise", {"pink"}}}).find("--noise: unknown noise model 'pink'"), std::string::npos);
  EXPECT_NE(error_of(std::nullopt, {{"origin", {"95,0,0"}}}).find("latitude 95"), std::string::npos);
  EXPECT_NE(error_of(std::nullopt, {{"origin", {"43,-89,-7000000"}}}).find("--origin: origin altitude -7000000 m"),
            std::string::npos);
  EXPECT_NE(error_of(std::nullopt, {{"origin", {"0,0,1e9"}}}).find("origin altitude 1000000000 m"), std::string::npos);
  EXPECT_NE(error_of(std::nullopt, {{"rate", {"2.5"}}}).find("--rate"), std::string::npos);
  EXPECT_NE(error_of(std::nullopt, {{"talker", {"XX"}}}).find("GP, GN"), std::string::npos);
  EXPECT_NE(error_of(std::nullopt, {{"start-time", {"noon"}}}).find("'noon'"), std::string::npos);
}

TEST(Config, ProtocolAndUbloxReceiverFromFlagsAndFileAndPerReceiverTable) {
  const Config d = build_config(std::nullopt, {});
  EXPECT_EQ(d.receiver().protocol, Protocol::nmea);
  EXPECT_EQ(d.receiver().receiver_model, ReceiverModel::generic);
  EXPECT_FALSE(d.receiver().sentences_given);
  const Config c = build_config(std::nullopt, {{"protocol", {"nmea+ubx"}}, {"receiver", {"ublox-f9p"}}, {"sentences", {"GGA"}}});
  EXPECT_EQ(c.receiver().protocol, Protocol::nmea_ubx);
  EXPECT_EQ(c.receiver().receiver_model, ReceiverModel::ublox_f9p);
  EXPECT_TRUE(c.receiver().sentences_given);
  // In a file `receiver` is the model (a string) or the [[receiver]] tables (TOML allows one of
  // them: with tables, each names its model); `protocol` may differ per receiver.
  const auto single = write_temp("ubx1.toml", "receiver = \"ublox-m9n\"\nprotocol = \"ubx\"\n");
  EXPECT_EQ(build_config(single, {}).receiver().receiver_model, ReceiverModel::ublox_m9n);
  const auto file = write_temp("ubx.toml", "protocol = \"ubx\"\n"
                                           "[[receiver]]\noutput = \"stdout\"\nreceiver = \"ublox-m9n\"\n"
                                           "[[receiver]]\noutput = \"file:/tmp/b\"\nprotocol = \"nmea\"\n");
  const Config f = build_config(file, {});
  ASSERT_EQ(f.receivers.size(), 2u);
  EXPECT_EQ(f.receivers[0].protocol, Protocol::ubx);
  EXPECT_EQ(f.receivers[0].receiver_model, ReceiverModel::ublox_m9n);
  EXPECT_EQ(f.receivers[1].protocol, Protocol::nmea);
  EXPECT_NE(error_of(std::nullopt, {{"protocol", {"rtcm"}}}).find("--protocol: protocol must be one of nmea, ubx, nmea+ubx"),
            std::string::npos);
}

TEST(Config, RateNeedsEnoughTimeDecimals) {
  EXPECT_NE(error_of(std::nullopt, {{"rate", {"20"}}, {"time-decimals", {"1"}}}).find("repeat a time"), std::string::npos);
  EXPECT_NO_THROW((void)build_config(std::nullopt, {{"rate", {"20"}}, {"time-decimals", {"2"}}}));
}

TEST(Config, WidthIsTheCgrwOneKnobUnlessAnAxisIsGiven) {
  const Config c = build_config(std::nullopt, {{"width", {"10"}}, {"cgrw-north", {"2,0.3,0.4,0.05"}}});
  EXPECT_DOUBLE_EQ(c.receiver().noise.cgrw.east.width_m, noise::cgrw_preset(10.0).east.width_m);
  EXPECT_DOUBLE_EQ(c.receiver().noise.cgrw.north.width_m, 2.0);
  EXPECT_DOUBLE_EQ(c.receiver().noise.cgrw.north.sigma_d2_m, 0.05);
}

TEST(Config, EveryOptionHasHelpWithAUnitOrDefault) {
  for (const auto& o : option_table()) {
    EXPECT_FALSE(o.help.empty()) << o.name;
    const bool documented = o.help.find("default") != std::string::npos || o.help.find("(") != std::string::npos;
    EXPECT_TRUE(documented) << o.name << ": " << o.help;
  }
}

}  // namespace config_test
}  // namespace
}  // namespace gpsemu

namespace gpsemu {
namespace {
namespace config_test {

// build_config_from_text (what config_fuzz drives) gives the file's messages word for word.
TEST(Config, TextAndFileGiveTheSameConfigAndMessages) {
  const std::vector<std::string> texts{
      "rate = 5\nlatency = 0.02\noutput = [\"stdout\", \"file:/tmp/x\"]\n",
      "rate = 5\n\nrate = 6\n",                 // TOML error: a key defined twice
      "speed_limit = 3\n",                      // unknown key
      "rate = 20\ntime-decimals = 1\n",         // derived-setting error
      "[[receiver]]\nseed = 3\n[[receiver]]\nrate = 2\n",  // a process-wide key in a receiver table
  };
  for (std::size_t i = 0; i < texts.size(); ++i) {
    const std::string path = write_temp("text" + std::to_string(i) + ".toml", texts[i]);
    std::string from_text = "(no error)";
    try {
      const Config c = build_config_from_text(texts[i], path, {{"seed", {"9"}}});
      const Config f = build_config(path, {{"seed", {"9"}}});
      EXPECT_EQ(c.timeline.rate_hz, f.timeline.rate_hz);
      EXPECT_EQ(test::output_texts(c.receiver().outputs), test::output_texts(f.receiver().outputs));
      EXPECT_EQ(c.receiver().seed, 9u);
    } catch (const ConfigError& e) {
      from_text = e.what();
    }
    EXPECT_EQ(from_text, error_of(path, {{"seed", {"9"}}})) << texts[i];
    if (i > 0) {
      EXPECT_NE(from_text, "(no error)") << texts[i];
    }
  }
}

}  // namespace config_test
}  // namespace
}  // namespace gpsemu
