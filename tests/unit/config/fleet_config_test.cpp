// Many receivers in one process: --receivers templating, [[receiver]] tables, and the refusals
// (shared outputs and ports, keys that belong to the whole process).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "emulator/config/fleet_config.hpp"
#include "tests/support/config_files.hpp"
#include "tests/support/output_texts.hpp"

namespace gpsemu {
namespace {
namespace fleet_config_test {

std::string write_temp(const std::string& name, const std::string& text) {
  return test::write_temp("gpsemu_fleet_", name, text);
}

std::string error_of(const std::optional<std::string>& file, const RawOptions& cli) { return test::config_error_of(file, cli); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(Fleet, TemplatesExpandToTheIndexAndAnOffset) {
  EXPECT_EQ(expand_receiver_template("output", "pty:/tmp/gps{i}", 7), "pty:/tmp/gps7");
  EXPECT_EQ(expand_receiver_template("source", "udp:{5600+i}", 7), "udp:5607");
  EXPECT_EQ(expand_receiver_template("source", "udp:127.0.0.1:{5600+i}", 0), "udp:127.0.0.1:5600");
  EXPECT_EQ(expand_receiver_template("output", "file:/tmp/r{i}/out{100+i}.nmea", 3), "file:/tmp/r3/out103.nmea");
  EXPECT_EQ(expand_receiver_template("output", "stdout", 3), "stdout");
  for (const char* bad : {"pty:/tmp/{j}", "udp:{i+5600}", "udp:{x+i}", "pty:/tmp/{i", "pty:/tmp/{}"}) {
    try {
      (void)expand_receiver_template("output", bad, 1);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_TRUE(contains(e.what(), "output '")) << e.what();
      EXPECT_TRUE(contains(e.what(), "{B+i}")) << e.what();
    }
  }
}

TEST(Fleet, OneReceiverIsTheConfigItself) {
  const Config c = build_config(std::nullopt, {{"seed", {"9"}}, {"output", {"file:/tmp/a.nmea"}}});
  const auto& fleet = c.receivers;
  ASSERT_EQ(fleet.size(), 1u);
  EXPECT_EQ(fleet[0].seed, 9u);
  EXPECT_EQ(test::output_texts(fleet[0].outputs), test::output_texts(c.receiver().outputs));
  EXPECT_EQ(to_string(fleet[0].source), to_string(c.receiver().source));
}

TEST(Fleet, ReceiversGetTheirOwnOutputsSourcesAndSeeds) {
  const auto fleet = build_config(std::nullopt, {{"receivers", {"256"}},
                                                                  {"seed", {"10"}},
                                                                  {"source", {"udp:{5600+i}"}},
                                                                  {"output", {"pty:/tmp/gps{i}", "udp:127.0.0.1:{7000+i}"}},
                                                                  {"tee", {"/tmp/tee{i}.log"}}}).receivers;
  ASSERT_EQ(fleet.size(), 256u);
  EXPECT_EQ(to_string(fleet[7].source), "udp:5607");
  EXPECT_EQ(test::output_texts(fleet[7].outputs), (std::vector<std::string>{"pty:/tmp/gps7", "udp:127.0.0.1:7007"}));
  EXPECT_EQ(fleet[7].tee, "/tmp/tee7.log");
  EXPECT_EQ(fleet[7].seed, 17u);
  EXPECT_EQ(to_string(fleet[255].source), "udp:5855");
}

TEST(Fleet, SimSourcesAndBarePtysMayBeGivenToEveryReceiver) {
  const auto fleet =
      build_config(std::nullopt, {{"receivers", {"3"}}, {"source", {"sim:circle"}}, {"output", {"pty"}}}).receivers;
  ASSERT_EQ(fleet.size(), 3u);
  EXPECT_EQ(to_string(fleet[2].source), "sim:circle");
}

TEST(Fleet, ASharedOutputOrSourceIsRefusedWithTheTemplateToUse) {
  // The default output, pty:/tmp/gpsemu, cannot serve two receivers.
  std::string e = error_of(std::nullopt, {{"receivers", {"3"}}});
  EXPECT_TRUE(contains(e, "output 'pty:/tmp/gpsemu' would be shared by all 3 receivers")) << e;
  EXPECT_TRUE(contains(e, "{i}")) << e;
  EXPECT_TRUE(contains(e, "pty:/tmp/gpsemu{i}")) << e;
  e = error_of(std::nullopt, {{"receivers", {"2"}}, {"output", {"file:/tmp/f{i}"}}, {"source", {"udp:5600"}}});
  EXPECT_TRUE(contains(e, "source 'udp:5600' would be shared")) << e;
  EXPECT_TRUE(contains(e, "udp:{5600+i}")) << e;
  e = error_of(std::nullopt, {{"receivers", {"2"}}, {"output", {"stdout"}}});
  EXPECT_TRUE(contains(e, "output 'stdout' would be shared")) << e;
  e = error_of(std::nullopt, {{"receivers", {"2"}}, {"output", {"pty{i}"}}, {"tee", {"/tmp/tee.log"}}});
  EXPECT_TRUE(contains(e, "tee '/tmp/tee.log' would be shared")) << e;
}

TEST(Fleet, TwoReceiversOnOneResourceAreNamed) {
  // Receiver 0's second output, o{1+i}, is receiver 1's first, o{i}.
  const std::string e = error_of(std::nullopt, {{"receivers", {"2"}}, {"output", {"file:/tmp/o{i}", "file:/tmp/o{1+i}"}}});
  EXPECT_TRUE(contains(e, "receiver 0 (output 'file:/tmp/o1') and receiver 1 (output 'file:/tmp/o1') would both "
                          "write to file /tmp/o1")) << e;
  const std::string ports = error_of(std::nullopt, {{"receivers", {"4"}}, {"output", {"tcp:{7000+i}"}},
                                                    {"source", {"tcp:{7002+i}"}}});
  EXPECT_TRUE(contains(ports, "listen on tcp port 7002")) << ports;
}

TEST(Fleet, OneReceiverNamingOneDestinationTwiceIsRefusedNamingBoth) {
  std::string e = error_of(std::nullopt, {{"output", {"stdout", "stdout"}}});
  EXPECT_TRUE(contains(e, "output 'stdout' and output 'stdout' would both write to stdout")) << e;
  e = error_of(std::nullopt, {{"output", {"file:/tmp/gpsemu_dup/a", "file:/tmp/gpsemu_dup/./b/../a"}}});
  EXPECT_TRUE(contains(e, "output 'file:/tmp/gpsemu_dup/a' and output 'file:/tmp/gpsemu_dup/./b/../a'")) << e;
  e = error_of(std::nullopt, {{"output", {"file:/tmp/gpsemu_dup/a?mode=append"}}, {"tee", {"/tmp/gpsemu_dup/a"}}});
  EXPECT_TRUE(contains(e, "and tee '/tmp/gpsemu_dup/a'")) << e;
  e = error_of(std::nullopt, {{"output", {"udp:127.0.0.1:9", "udp:127.0.0.1:9"}}});
  EXPECT_TRUE(contains(e, "would both write to udp destination 127.0.0.1:9")) << e;
  e = error_of(std::nullopt, {{"receivers", {"2"}}, {"output", {"pty:/tmp/g{i}", "pty:/tmp/g{i}"}}});
  EXPECT_TRUE(contains(e, "receiver 0: output 'pty:/tmp/g0' and output 'pty:/tmp/g0'")) << e;
  EXPECT_EQ(error_of(std::nullopt, {{"output", {"pty", "pty", "tcp:0", "tcp:0", "stdout"}}}), "(no error)");
}

TEST(Fleet, ReceiverTablesOverrideTheSharedSettings) {
  const auto file = write_temp("a.toml",
                               "rate = 5\n"
                               "seed = 3\n"
                               "noise = \"gaussian\"\n"
                               "output = [\"file:/tmp/shared{i}.nmea\"]\n"
                               "\n"
                               "[[receiver]]\n"
                               "source = \"udp:5601\"\n"
                               "output = [\"pty:/tmp/car1\"]\n"
                               "\n"
                               "[[receiver]]\n"
                               "source = \"udp:5602\"\n"
                               "seed = 70\n"
                               "width = 3\n"
                               "noise = \"cgrw\"\n"
                               "origin = \"44,-89,100\"\n"
                               "\n"
                               "[[receiver]]\n"
                               "source = \"sim:circle\"\n");
  const Config shared = build_config(file, {{"noise", {"none"}}});
  EXPECT_EQ(shared.receivers.size(), 3u);
  const auto& fleet = shared.receivers;
  ASSERT_EQ(fleet.size(), 3u);
  EXPECT_EQ(to_string(fleet[0].source), "udp:5601");
  EXPECT_EQ(test::output_texts(fleet[0].outputs), std::vector<std::string>{"pty:/tmp/car1"});
  EXPECT_EQ(fleet[0].seed, 3u);
  EXPECT_EQ(fleet[0].noise.model, noise::Model::none);  // the command line beats the file's top level
  EXPECT_DOUBLE_EQ(shared.timeline.rate_hz, 5.0);
  EXPECT_EQ(fleet[1].seed, 70u);
  EXPECT_EQ(fleet[1].noise.model, noise::Model::cgrw);  // a table beats the command line
  EXPECT_DOUBLE_EQ(fleet[1].noise.cgrw.east.width_m, noise::cgrw_preset(3.0).east.width_m);
  EXPECT_DOUBLE_EQ(fleet[1].origin.lat_deg, 44.0);
  EXPECT_DOUBLE_EQ(fleet[0].origin.lat_deg, 43.0725);
  EXPECT_EQ(to_string(fleet[2].source), "sim:circle");
  EXPECT_EQ(test::output_texts(fleet[2].outputs), std::vector<std::string>{"file:/tmp/shared2.nmea"});
  EXPECT_EQ(fleet[2].seed, 5u);
}

TEST(Fleet, ProcessKeysInATableAreRefusedWithFileLineAndWhy) {
  struct Case {
    const char* key_line;
    const char* why;
  };
  for (const Case& c : {Case{"rate = 5", "one epoch timeline"}, Case{"latency = 0.1", "one epoch timeline"},
                        Case{"pps = \"modem:RTS\"", "one PPS line"}, Case{"log-level = \"warn\"", "whole process"},
                        Case{"receivers = 2", "number of [[receiver]] tables"},
                        Case{"speed = 2", "gpsemu replay"}, Case{"clock = \"lockstep\"", "one epoch timeline"}}) {
    const auto file = write_temp("b.toml", std::string("[[receiver]]\nsource = \"sim:line\"\n") + c.key_line + "\n");
    const std::string e = error_of(file, {});
    const std::string key = std::string(c.key_line).substr(0, std::string(c.key_line).find(' '));
    EXPECT_TRUE(contains(e, "b.toml:3: key '" + key + "' cannot be set in a [[receiver]] table")) << e;
    EXPECT_TRUE(contains(e, c.why)) << e;
  }
  const auto unknown = write_temp("c.toml", "[[receiver]]\nwidht = 2\n");
  EXPECT_TRUE(contains(error_of(unknown, {}), "c.toml:2: unknown key 'widht' in a [[receiver]] table"))
      << error_of(unknown, {});
  const auto bad_value = write_temp("d.toml", "[[receiver]]\n\norigin = \"95,0,0\"\n");
  EXPECT_TRUE(contains(error_of(bad_value, {}), "d.toml:3: [[receiver]] key 'origin'")) << error_of(bad_value, {});
  EXPECT_TRUE(contains(error_of(bad_value, {}), "latitude 95")) << error_of(bad_value, {});
  const auto not_tables = write_temp("e.toml", "receiver = 3\n");
  EXPECT_TRUE(contains(error_of(not_tables, {}), "e.toml:1: 'receiver' must be [[receiver]] tables"))
      << error_of(not_tables, {});
}

TEST(Fleet, ReceiversMustMatchTheTables) {
  const auto file = write_temp("f.toml", "[[receiver]]\noutput = \"pty:/tmp/a\"\n[[receiver]]\noutput = \"pty:/tmp/b\"\n");
  EXPECT_EQ(build_config(file, {{"receivers", {"2"}}}).receivers.size(), 2u);
  const std::string e = error_of(file, {{"receivers", {"3"}}});
  EXPECT_TRUE(contains(e, "receivers is 3 but config file")) << e;
  EXPECT_TRUE(contains(e, "has 2 [[receiver]] tables")) << e;
  const auto top = write_temp("g.toml", "receivers = 5\n[[receiver]]\noutput = \"pty:/tmp/a\"\n");
  EXPECT_TRUE(contains(error_of(top, {}), "receivers is 5")) << error_of(top, {});
}

TEST(Fleet, TablesWritingTheSameOutputAreNamedByFileAndLine) {
  const auto file = write_temp("h.toml", "[[receiver]]\noutput = \"pty:/tmp/car\"\n\n[[receiver]]\nsource = "
                                         "\"udp:5601\"\n[[receiver]]\noutput = \"pty:/tmp/car\"\n");
  const std::string e = error_of(file, {});
  EXPECT_TRUE(contains(e, "receiver 0 ([[receiver]] at ")) << e;
  EXPECT_TRUE(contains(e, "h.toml:1, output 'pty:/tmp/car')")) << e;
  EXPECT_TRUE(contains(e, "receiver 2 ([[receiver]] at ")) << e;
  EXPECT_TRUE(contains(e, "h.toml:6, output 'pty:/tmp/car')")) << e;
  EXPECT_TRUE(contains(e, "pty link /tmp/car")) << e;
}

TEST(Fleet, ReceiverCountIsChecked) {
  EXPECT_TRUE(contains(error_of(std::nullopt, {{"receivers", {"0"}}}), "--receivers")) << error_of(std::nullopt, {{"receivers", {"0"}}});
  EXPECT_TRUE(contains(error_of(std::nullopt, {{"receivers", {"1025"}}}), "--receivers"));
  EXPECT_TRUE(contains(error_of(std::nullopt, {{"receivers", {"2.5"}}}), "whole number"));
}

// --rtcm in a fleet: one base-station port a receiver, from a template or each table's own key.
TEST(Fleet, EachReceiverTakesItsOwnRtcmPort) {
  const auto fleet = build_config(std::nullopt, {{"receivers", {"3"}},
                                                 {"output", {"pty:/tmp/gps{i}"}},
                                                 {"rtcm", {"udp:{2101+i}"}}}).receivers;
  ASSERT_EQ(fleet.size(), 3u);
  for (std::size_t i = 0; i < fleet.size(); ++i) {
    ASSERT_TRUE(fleet[i].rtcm.has_value());
    EXPECT_FALSE(fleet[i].rtcm->tcp);
    EXPECT_EQ(fleet[i].rtcm->endpoint.port, 2101 + i);
  }
  const auto file = write_temp("rtcm.toml",
                               "output = \"pty:/tmp/gps{i}\"\n"
                               "[[receiver]]\n"
                               "rtcm = \"tcp:2201\"\n"
                               "[[receiver]]\n"
                               "[[receiver]]\n"
                               "rtcm = \"udp:127.0.0.1:2202\"\n");
  const auto tables = build_config(file, {}).receivers;
  ASSERT_EQ(tables.size(), 3u);
  ASSERT_TRUE(tables[0].rtcm.has_value());
  EXPECT_TRUE(tables[0].rtcm->tcp);
  EXPECT_EQ(tables[0].rtcm->endpoint.port, 2201);
  EXPECT_FALSE(tables[1].rtcm.has_value());  // no corrections input: RTCM3 on its u-blox port only
  ASSERT_TRUE(tables[2].rtcm.has_value());
  EXPECT_EQ(tables[2].rtcm->endpoint.port, 2202);
}

TEST(Fleet, ASharedRtcmPortIsRefusedWithTheTemplateToUse) {
  std::string e = error_of(std::nullopt, {{"receivers", {"2"}}, {"output", {"pty:/tmp/g{i}"}}, {"rtcm", {"tcp:2101"}}});
  EXPECT_TRUE(contains(e, "rtcm 'tcp:2101' would be shared by all 2 receivers")) << e;
  EXPECT_TRUE(contains(e, "listen on tcp port 2101")) << e;
  EXPECT_TRUE(contains(e, "tcp:{2101+i}")) << e;
  // A receiver's corrections port that is another's pose port.
  e = error_of(std::nullopt, {{"receivers", {"2"}}, {"output", {"pty:/tmp/g{i}"}}, {"source", {"udp:{5600+i}"}},
                              {"rtcm", {"udp:{5599+i}"}}});
  EXPECT_TRUE(contains(e, "would both listen on udp port 5600")) << e;
  e = error_of(std::nullopt, {{"rtcm", {"udp:{i+x}"}}});
  EXPECT_TRUE(contains(e, "rtcm")) << e;
}

}  // namespace fleet_config_test
}  // namespace
}  // namespace gpsemu
