// Where a test finds what the build made and the source tree holds: the gpsemu binary, the
// gpsemu-timing reader, the checkout. The tests name them as GPSEMU_BINARY, GPSEMU_TIMING_BINARY and
// GPSEMU_SOURCE_DIR, macros that call these functions (tests/CMakeLists.txt puts them on every test's
// command line and includes this header first). The absolute paths are compiled once, into
// tests/support/paths.cpp: every other test object is then the same in any checkout, so ccache
// reuses it in a fresh clone (CI's) or a worktree.
#pragma once

namespace gpsemu::test {

const char* gpsemu_binary();   ///< the build's gpsemu executable (absolute path)
const char* timing_binary();   ///< the build's gpsemu-timing executable (absolute path)
const char* source_dir();      ///< the checkout's top directory (absolute path)

}  // namespace gpsemu::test
