// The absolute paths of the build and the checkout, compiled once (tests/support/paths.hpp).
#include "tests/support/paths.hpp"

namespace gpsemu::test {

const char* gpsemu_binary() { return GPSEMU_TEST_PATH_BINARY; }
const char* timing_binary() { return GPSEMU_TEST_PATH_TIMING_BINARY; }
const char* source_dir() { return GPSEMU_TEST_PATH_SOURCE_DIR; }

}  // namespace gpsemu::test
