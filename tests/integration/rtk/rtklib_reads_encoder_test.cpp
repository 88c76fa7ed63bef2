// The project's RTCM3 encoder against a real decoder: RTKLIB's convbin (Debian package rtklib,
// tools/setup --with-test-deps) turns a stream of 1006 + GPS MSM7 + GLONASS MSM4 frames written
// by rtk::append_rtcm3_frame into RINEX observations: every epoch and satellite comes back. A frame
// with a bad CRC is skipped by convbin as by rtk::Rtcm3Reader.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <fmt/format.h>

#include "emulator/rtk/rtcm3_messages.hpp"
#include "emulator/rtk/rtcm3_reader.hpp"
#include "tests/support/process.hpp"
#include "tests/support/scratch.hpp"

namespace gpsemu::rtk {
namespace {
namespace rtklib_reads_encoder_test {

namespace fs = std::filesystem;
constexpr const char* kConvbin = "/usr/bin/convbin";

TEST(RtklibReadsEncoder, ConvbinDecodesEveryEpochAndSatellite) {
  ASSERT_EQ(::access(kConvbin, X_OK), 0) << "convbin is missing: tools/setup --with-test-deps installs rtklib";
  const fs::path dir = test::scratch_root() / fmt::format("gpsemu_rtklib_{}", ::getpid());
  fs::create_directories(dir);
  std::string stream;
  append_rtcm3_frame(stream, encode_base_position({42, 1114104.5999, -4850729.7108, 3975521.4643, 1.5}, true));
  for (int k = 0; k < 5; ++k) {
    append_rtcm3_frame(stream, encode_msm(1077, 42, 345600000u + 1000u * static_cast<std::uint32_t>(k), 8, 1));
  }
  std::string bad = rtcm3_frame_bytes(encode_msm(1077, 42, 345605000u, 8, 1));
  bad[10] = static_cast<char>(bad[10] ^ 0x01);
  stream += bad;
  {
    std::ofstream out(dir / "in.rtcm3", std::ios::binary);
    out << stream;
  }
  const auto r = test::run({kConvbin, "-r", "rtcm3", "-tr", "2026/11/26", "00:00:00", "-o",
                                    (dir / "out.obs").string(), (dir / "in.rtcm3").string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("O=5"), std::string::npos) << r.err;  // five epochs, not six: the bad CRC is skipped
  std::ifstream obs(dir / "out.obs");
  std::stringstream text;
  text << obs.rdbuf();
  const std::string rinex = text.str();
  const auto body = rinex.find("END OF HEADER");
  ASSERT_NE(body, std::string::npos) << rinex;
  // Satellites G01..G08 (the encoder's mask), one line each an epoch.
  int lines = 0;
  const std::regex sat_line(R"(\nG0[1-8] +[0-9])");
  for (auto it = std::sregex_iterator(rinex.begin() + static_cast<long>(body), rinex.end(), sat_line);
       it != std::sregex_iterator(); ++it) {
    ++lines;
  }
  EXPECT_EQ(lines, 5 * 8) << rinex.substr(body);
  fs::remove_all(dir);
}

}  // namespace rtklib_reads_encoder_test
}  // namespace
}  // namespace gpsemu::rtk
