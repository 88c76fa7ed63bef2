// tools/gpsemu, the README's `gpsemu` from a checkout (issue 33 point 8): it runs this build's
// binary with the arguments given, and says what to do when nothing is built.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>

#include "tests/support/process.hpp"

namespace gpsemu {
namespace {
namespace tools_gpsemu_test {

TEST(ToolsGpsemu, RunsTheBuildsBinaryWithItsArguments) {
  const std::filesystem::path build = std::filesystem::path(GPSEMU_BINARY).parent_path().parent_path();
  ASSERT_EQ(::setenv("GPSEMU_BUILD_DIR", build.c_str(), 1), 0);
  const std::string wrapper = (std::filesystem::path(GPSEMU_SOURCE_DIR) / "tools" / "gpsemu").string();
  const test::Result direct = test::run({GPSEMU_BINARY, "--version"});
  const test::Result wrapped = test::run({wrapper, "--version"});
  EXPECT_EQ(wrapped.status, 0) << wrapped.err;
  EXPECT_EQ(wrapped.out, direct.out);
  EXPECT_FALSE(wrapped.out.empty());

  ASSERT_EQ(::setenv("GPSEMU_BUILD_DIR", "/nonexistent/build", 1), 0);
  const test::Result missing = test::run({wrapper, "--version"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("/nonexistent/build/emulator/gpsemu is not built yet: run tools/setup"), std::string::npos)
      << missing.err;
  ::unsetenv("GPSEMU_BUILD_DIR");
}

}  // namespace tools_gpsemu_test
}  // namespace
}  // namespace gpsemu
