// Under AddressSanitizer (tools/reliability) freed memory sits in a 256 MB quarantine, so a child's
// RSS says nothing about what it keeps: a memory test runs its child without the quarantine.
#pragma once

#include <cstdlib>
#include <string>

// GCC defines __SANITIZE_ADDRESS__; clang (the CI's sanitizer tree) answers __has_feature instead.
#if defined(__SANITIZE_ADDRESS__)
#define GPSEMU_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GPSEMU_TEST_ASAN 1
#endif
#endif

namespace gpsemu::test {

/// Children started after this run without ASan's quarantine (no effect without ASan).
inline void without_asan_quarantine() {
#if defined(GPSEMU_TEST_ASAN)
  const char* options = std::getenv("ASAN_OPTIONS");
  const std::string merged =
      std::string(options ? options : "") + (options && *options ? ":" : "") + "quarantine_size_mb=0";
  ::setenv("ASAN_OPTIONS", merged.c_str(), 1);
#endif
}

}  // namespace gpsemu::test
