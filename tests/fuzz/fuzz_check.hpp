// Shared by the libFuzzer targets: an invariant that does not hold is a crash, so libFuzzer saves
// the input and the run fails (also with -fsanitize flags that do not trap).
#pragma once

#include <cstdio>
#include <cstdlib>

#define GPSEMU_FUZZ_CHECK(condition)                                                            \
  do {                                                                                          \
    if (!(condition)) {                                                                         \
      std::fprintf(stderr, "%s:%d: invariant failed: %s\n", __FILE__, __LINE__, #condition);     \
      std::abort();                                                                             \
    }                                                                                           \
  } while (false)
