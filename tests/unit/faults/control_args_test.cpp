// gpsemu ctl's words as a control request: every parameter of every kind has a flag from the
// catalogue (with and without its unit), --FLAG=VALUE works, and a word too many or an unknown
// flag is refused with the kind's flags listed.
#include "emulator/faults/control_args.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "emulator/faults/catalogue.hpp"
#include "emulator/faults/fault.hpp"

namespace gpsemu::faults {
namespace {
namespace control_args_test {

using nlohmann::json;

json request(const std::vector<std::string>& words) { return json::parse(control_request_of(words)); }

std::string refusal(const std::vector<std::string>& words) {
  try {
    (void)control_request_of(words);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(ControlArgs, SpoofAndLatencyTakeEveryParameterWithOrWithoutItsUnit) {
  EXPECT_EQ(request({"spoof", "--speed", "2", "--bearing", "45"}),
            json({{"fault", "spoof"}, {"speed_mps", 2.0}, {"bearing_deg", 45.0}}));
  EXPECT_EQ(request({"spoof", "--speed-mps", "2", "--time-drift", "-3", "--detected"}),
            json({{"fault", "spoof"}, {"speed_mps", 2.0}, {"time_drift_ms_per_s", -3.0}, {"detected", "true"}}));
  EXPECT_EQ(request({"latency", "--delay", "300", "--jitter-ms", "50", "--duration", "2"}),
            json({{"fault", "latency"}, {"delay_ms", 300.0}, {"jitter_ms", 50.0}, {"duration", 2.0}}));
  EXPECT_EQ(request({"jam", "--db=25", "--ramp-out=3", "--receiver", "all"}),
            json({{"fault", "jam"}, {"db", 25.0}, {"ramp_out_s", 3.0}, {"receiver", "all"}}));
  EXPECT_EQ(request({"reset", "--silent", "1", "--ttff-s", "5"}), json({{"fault", "reset"}, {"silent_s", 1.0}, {"ttff_s", 5.0}}));
  EXPECT_EQ(request({"time", "--mode", "jump", "--jump", "0.5"}), json({{"fault", "time"}, {"mode", "jump"}, {"jump_s", 0.5}}));
}

TEST(ControlArgs, EveryParameterOfEveryKindHasAFlagTheSocketAccepts) {
  for (const KindInfo& k : catalogue()) {
    for (const std::string_view key : parameters_of(k.kind)) {
      const std::string flag = "--" + std::string(key_without_unit(key));
      std::string dashed = flag;
      for (char& c : dashed) c = c == '_' ? '-' : c;
      const json r = request({std::string(k.name), dashed, "1"});
      EXPECT_TRUE(r.contains(std::string(key))) << k.name << " " << dashed << ": " << r.dump();
    }
  }
}

TEST(ControlArgs, ExtraWordsUnknownFlagsAndMissingValuesAreRefused) {
  EXPECT_NE(refusal({"status", "now"}).find("unexpected word 'now'"), std::string::npos);
  EXPECT_NE(refusal({"clear", "jam", "extra"}).find("unexpected word 'extra'"), std::string::npos);
  EXPECT_NE(refusal({"jam", "--db", "25", "30"}).find("unexpected word '30'"), std::string::npos);
  const std::string unknown = refusal({"jam", "--speed", "3"});
  EXPECT_NE(unknown.find("unknown flag --speed"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("--db"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("--ramp-out-s|--ramp-out"), std::string::npos) << unknown;
  EXPECT_NE(refusal({"jam", "--db"}).find("--db needs a value"), std::string::npos);
  EXPECT_NE(refusal({"jam", "--db", "1", "--db", "2"}).find("given twice"), std::string::npos);
  EXPECT_NE(refusal({"meteor"}).find("unknown command 'meteor'"), std::string::npos);
  EXPECT_NE(refusal({"send", "{}", "{}"}).find("one JSON line"), std::string::npos);
  EXPECT_NE(refusal({"jam", "--at", "3"}).find("unknown flag --at"), std::string::npos);
}

TEST(ControlArgs, ALiveErrorListsOnlyTheKeysALiveRequestTakes) {
  try {
    (void)make_fault({{"kind", std::string("jam")}, {"db", 25.0}, {"ramp", 2.0}}, FaultSource::live);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("every live fault: fault, duration, where, receiver"), std::string::npos) << m;
    EXPECT_EQ(m.find("at_utc"), std::string::npos) << m;
  }
}

TEST(ControlArgs, TheHelpNamesEveryKindAndItsFlags) {
  const std::string help = control_flags_help();
  for (const KindInfo& k : catalogue()) EXPECT_NE(help.find("  " + std::string(k.name) + ": "), std::string::npos) << k.name;
  EXPECT_NE(help.find("spoof: --bearing-deg|--bearing"), std::string::npos) << help;
  EXPECT_NE(help.find("latency: --delay-ms|--delay, --jitter-ms|--jitter"), std::string::npos) << help;
  EXPECT_NE(help.find("  --db: C/N0 drop at full strength, dB, 0..60\n"), std::string::npos) << help;
  EXPECT_NE(help.find("  --speed-mps|--speed: drag speed, m/s, 0..1000\n"), std::string::npos) << help;
}

}  // namespace control_args_test
}  // namespace
}  // namespace gpsemu::faults
