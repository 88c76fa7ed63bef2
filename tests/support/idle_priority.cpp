// Linked into the CPU-bound test executables (tests/CMakeLists.txt): when CTest runs one of their
// tests with GPSEMU_TEST_SCHED_IDLE=1 in its environment, the process (and every gpsemu it starts,
// which inherits the class) moves to the idle scheduling class before main. It then gets a core
// only while no normal task wants it: a timing test beside it wakes up and runs at once (the kernel
// preempts an idle-class task for any other), so the CPU-bound tests fill the time the timing tests
// spend waiting instead of waiting for them. Without the variable (a developer running the
// executable by hand, CTest's test discovery) nothing changes.
#include <sched.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace {

bool enter_idle_class() {
  const char* wanted = std::getenv("GPSEMU_TEST_SCHED_IDLE");
  if (wanted == nullptr || std::string_view(wanted) != "1") return false;
  const sched_param param{};
  if (::sched_setscheduler(0, SCHED_IDLE, &param) != 0) {
    std::fprintf(stderr, "GPSEMU_TEST_SCHED_IDLE=1: could not enter the idle scheduling class: %s; running as is\n",
                 std::strerror(errno));
    return false;
  }
  return true;
}

[[maybe_unused]] const bool kIdle = enter_idle_class();

}  // namespace
