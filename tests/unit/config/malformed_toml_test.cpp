// 47 malformed config files (issue 22: "what held up and must keep holding"): TOML syntax errors,
// wrong types, values out of range, unknown keys and tables, duplicates, odd bytes. Each is
// refused with one ConfigError line that names the file and what was wrong (its line, or its key),
// never accepted and never more than one line. Table-driven: the file's text and a part of the
// message it must give.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "tests/support/config_files.hpp"

namespace gpsemu {
namespace {
namespace malformed_toml_test {

struct Malformed {
  const char* what;
  std::string text;
  const char* says;  ///< a part of the message (a line ":N:" or a key)
  bool names_file = true;  ///< false: a value checked after the file was read (an output spec) names itself only
};

std::vector<Malformed> malformed_files() {
  return {
      // TOML syntax
      {"value missing", "rate = \n", ":1:"},
      {"no equals sign", "rate 5\n", ":1:"},
      {"unclosed string", "output = \"stdout\n", ":1:"},
      {"unclosed array", "output = [\"stdout\",\n", ":"},
      {"unclosed table header", "[[receiver]\noutput = \"stdout\"\n", ":1:"},
      {"bare word value", "talker = GP\n", ":1:"},
      {"two values on one line", "rate = 5 6\n", ":1:"},
      {"key without value on line 3", "# a\n\nseed =\n", ":3:"},
      {"duplicate key", "rate = 5\nrate = 6\n", ":2:"},
      {"duplicate table", "[a]\nx = 1\n[a]\ny = 2\n", ":3:"},
      {"invalid escape", "output = \"std\\qout\"\n", ":1:"},
      {"bad number", "rate = 5..0\n", ":1:"},
      {"leading zero integer", "seed = 007\n", ":1:"},
      {"bad date", "start-time = 2024-13-45T00:00:00Z\n", ":1:"},
      {"NUL byte", std::string("rate = 5\n\0\n", 11), ":2:"},
      {"mixed array types", "output = [\"stdout\", 5]\n", "output"},
      {"inline table unclosed", "x = { a = 1\n", ":1:"},
      {"only a header of an array of tables", "[[]]\n", ":1:"},
      {"control character in a string", "talker = \"G\x01P\"\n", ":1:"},
      {"unterminated multi-line string", "output = \"\"\"stdout\n", ":1:"},
      // Unknown keys and tables
      {"unknown key", "rate = 5\nratte = 3\n", "unknown key 'ratte'"},
      {"unknown key in a receiver table", "[[receiver]]\noutputt = \"stdout\"\n", "outputt"},
      {"unknown table", "[sky]\nfoo = 1\n", "sky"},
      {"key in the wrong case", "Rate = 5\n", "Rate"},
      {"key with an underscore", "start_time = \"2024-05-01T00:00:00Z\"\n", "start_time"},
      // Wrong types
      {"a number for text", "output = 5\n", "key 'output': expected a string (SPEC), got an integer (5)"},
      {"a boolean for a number", "rate = true\n", "rate"},
      {"a string for a number", "rate = \"fast\"\n", "rate"},
      {"a string for a duration", "latency = \"soon\"\n", "latency"},
      {"a table for a number", "rate = { hz = 5 }\n", "rate"},
      {"a float for an integer", "seed = 1.5\n", "seed"},
      {"a negative duration", "duration = -5\n", "duration"},
      {"a date for text", "talker = 2024-05-01\n", "talker"},
      {"a float for text in a receiver table", "[[receiver]]\noutput = 7.5\n", "got a number"},
      // Values out of range or unknown
      {"rate too high", "rate = 500\n", "from 0.1 to 50"},
      {"rate zero", "rate = 0\n", "rate"},
      {"rate negative", "rate = -1\n", "rate"},
      {"rate NaN", "rate = nan\n", "rate"},
      {"rate infinite", "rate = inf\n", "rate"},
      {"latency negative", "latency = -0.5\n", "latency"},
      {"unknown noise model", "noise = \"brownian\"\n", "noise"},
      {"unknown talker", "talker = \"XX\"\n", "talker"},
      {"unknown sentence", "sentences = \"RMC,FOO\"\n", "sentences"},
      {"latitude out of range", "origin = \"91,0,0\"\n", "origin"},
      {"altitude out of range", "origin = \"45,8,2000000\"\n", "origin"},
      {"start time without Z", "start-time = \"2024-05-01T00:00:00\"\n", "start-time"},
      {"unknown output kind", "output = \"carrier-pigeon:1\"\n", "invalid output spec 'carrier-pigeon:1'", false},
  };
}

TEST(MalformedToml, EveryMalformedFileIsRefusedInOneLineNamingWhatWasWrong) {
  const std::vector<Malformed> files = malformed_files();
  ASSERT_EQ(files.size(), 47u);
  std::size_t k = 0;
  for (const Malformed& m : files) {
    const std::string name = "malformed_" + std::to_string(k++) + ".toml";
    const std::string path = test::write_temp("gpsemu_cfg_", name, m.text);
    const std::string e = test::config_error_of(path, {});
    EXPECT_NE(e, "(no error)") << m.what << ": accepted";
    if (m.names_file) {
      EXPECT_NE(e.find(name), std::string::npos) << m.what << ": the message names no file: " << e;
    }
    EXPECT_NE(e.find(m.says), std::string::npos) << m.what << ": expected '" << m.says << "' in: " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << m.what << ": more than one line: " << e;
    EXPECT_LE(e.size(), 1000u) << m.what;
    std::remove(path.c_str());
  }
}

}  // namespace malformed_toml_test
}  // namespace
}  // namespace gpsemu
