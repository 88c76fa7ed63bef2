// Output specs: which texts parse to which OutputSpec, which are refused and with what message,
// and that make_output() opens the backend a spec names.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "transport/output_spec.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::transport {
namespace {
namespace spec_test {

namespace fs = std::filesystem;
using namespace std::string_literals;

struct ValidCase {
  std::string text;
  OutputSpec expected;
};

TEST(OutputSpecTest, ValidSpecsParse) {
  const std::vector<ValidCase> cases = {
      {"pty", {OutputKind::pty, {}}},
      {"pty:/tmp/gpsemu", {OutputKind::pty, "/tmp/gpsemu"}},
      {"pty:gps0", {OutputKind::pty, "gps0"}},
      {"pty:/tmp/with:colon", {OutputKind::pty, "/tmp/with:colon"}},
      {"file:out.nmea", {OutputKind::file, "out.nmea"}},
      {"file:/var/log/gps/run 1.nmea", {OutputKind::file, "/var/log/gps/run 1.nmea"}},
      {"file:C:x", {OutputKind::file, "C:x"}},
      {"stdout", {OutputKind::standard_output, {}}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    const OutputSpec spec = parse_output_spec(c.text);
    EXPECT_EQ(spec, c.expected);
    EXPECT_EQ(to_string(spec), c.text);
  }
}

TEST(OutputSpecTest, InvalidSpecsThrowNamingTheSpecAndTheAcceptedForms) {
  // The spec as typed, and as the message must show it (control bytes escaped).
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", ""},
      {"pty:", "pty:"},
      {"file", "file"},
      {"file:", "file:"},
      {"stdout:", "stdout:"},
      {"stdout:x", "stdout:x"},
      {"tty", "tty"},
      {"PTY", "PTY"},
      {" pty", " pty"},
      {"pty ", "pty "},
      {"files:x", "files:x"},
      {"-", "-"},
      {"serial:/dev/ttyUSB0@9601", "serial:/dev/ttyUSB0@9601"},
      {"tcp:", "tcp:"},
      {"udp:10110", "udp:10110"},
      {"pty:/tmp/a\0b"s, "pty:/tmp/a\\x00b"},
      {"stdout\n", "stdout\\x0a"},
  };
  for (const auto& [text, shown] : cases) {
    SCOPED_TRACE(shown);
    try {
      (void)parse_output_spec(text);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("'" + shown + "'"), std::string::npos) << what;
      EXPECT_NE(what.find("pty[:LINK]"), std::string::npos) << what;
      EXPECT_NE(what.find("file:PATH"), std::string::npos) << what;
      EXPECT_NE(what.find("stdout"), std::string::npos) << what;
    }
  }
}

TEST(OutputSpecTest, FileModesParseAndReadBack) {
  const OutputSpec append = parse_output_spec("file:out.nmea?mode=append");
  EXPECT_EQ(append.path, "out.nmea");
  EXPECT_EQ(append.file_mode, FileMode::append);
  EXPECT_EQ(to_string(append), "file:out.nmea?mode=append");
  const OutputSpec fresh = parse_output_spec("file:/tmp/a?b?mode=new");  // the last '?mode=' only
  EXPECT_EQ(fresh.path, "/tmp/a?b");
  EXPECT_EQ(fresh.file_mode, FileMode::create_new);
  EXPECT_EQ(to_string(fresh), "file:/tmp/a?b?mode=new");
  EXPECT_EQ(parse_output_spec("file:a?mode=truncate"), parse_output_spec("file:a"));
  EXPECT_EQ(parse_output_spec("file:what?").path, "what?");  // a '?' without mode= is part of the path
  for (const std::string bad : {"file:a?mode=", "file:a?mode=APPEND", "file:?mode=new"}) {
    SCOPED_TRACE(bad);
    EXPECT_THROW((void)parse_output_spec(bad), std::invalid_argument);
  }
}

TEST(OutputSpecTest, SerialTcpAndUdpKindsParse) {
  // Their forms in detail: transport_serial_test, transport_tcp_test, transport_udp_test.
  EXPECT_EQ(parse_output_spec("serial:/dev/ttyUSB0").kind, OutputKind::serial);
  EXPECT_EQ(parse_output_spec("tcp:2947").kind, OutputKind::tcp);
  EXPECT_EQ(parse_output_spec("udp:127.0.0.1:10110").kind, OutputKind::udp);
}

class MakeOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (test::scratch_root() / "gpsemu_spec_XXXXXX").string();
    ASSERT_NE(::mkdtemp(templ.data()), nullptr);
    dir_ = templ;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

using test::read_file;

TEST_F(MakeOutputTest, RealTimeFileHandsOverEachEpoch) {
  const fs::path path = dir_ / "out.nmea";
  const auto out = make_output(parse_output_spec("file:" + path.string()), {.realtime = true});
  EXPECT_EQ(out->describe(), "file " + path.string());
  ASSERT_EQ(out->write_epoch("$GPZDA*00\r\n"), WriteStatus::ok);
  EXPECT_EQ(read_file(path), "$GPZDA*00\r\n");
}

TEST_F(MakeOutputTest, FastFileBuffersUntilFlush) {
  const fs::path path = dir_ / "out.nmea";
  const auto out = make_output(parse_output_spec("file:" + path.string()), {.realtime = false});
  ASSERT_EQ(out->write_epoch("$GPZDA*00\r\n"), WriteStatus::ok);
  EXPECT_EQ(read_file(path), "");
  out->flush();
  EXPECT_EQ(read_file(path), "$GPZDA*00\r\n");
}

TEST_F(MakeOutputTest, PtyWithLinkAndStdout) {
  const fs::path link = dir_ / "gps";
  {
    const auto pty = make_output(parse_output_spec("pty:" + link.string()), {});
    ASSERT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(pty->describe(), fs::read_symlink(link).string() + " (link " + link.string() + ")");
    EXPECT_GE(pty->poll_fd(), 0);
  }
  EXPECT_FALSE(fs::exists(fs::symlink_status(link)));
  EXPECT_EQ(make_output(parse_output_spec("pty"), {})->describe().rfind("/dev/pts/", 0), 0u);
  EXPECT_EQ(make_output(parse_output_spec("stdout"), {})->describe(), "stdout");
}

TEST_F(MakeOutputTest, UnopenableFileThrowsNamingPath) {
  const fs::path path = dir_ / "missing" / "out.nmea";
  try {
    (void)make_output(parse_output_spec("file:" + path.string()), {});
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

}  // namespace spec_test
}  // namespace
}  // namespace gpsemu::transport
