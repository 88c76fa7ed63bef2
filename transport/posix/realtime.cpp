#include "transport/posix/realtime.hpp"

#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>

#include <cerrno>

#include <fmt/format.h>

#include "transport/posix/errors.hpp"

namespace gpsemu::posix {
namespace {

std::string why(int error) {
  if (error == EPERM) return "not permitted (run as root, with CAP_SYS_NICE / CAP_IPC_LOCK, or raise the "
                             "rtprio / memlock limits in /etc/security/limits.conf)";
  if (error == ENOMEM) return "not permitted: the memlock limit is too small (ulimit -l; CAP_IPC_LOCK)";
  return errno_text(error);
}

}  // namespace

std::vector<std::string> apply_realtime_settings(const RealtimeSettings& settings) {
  std::vector<std::string> report;
  if (settings.timer_slack_ns) {
    if (::prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(*settings.timer_slack_ns), 0, 0, 0) == 0) {
      report.push_back(fmt::format("timer slack {} ns", *settings.timer_slack_ns));
    } else {
      report.push_back(fmt::format("timer slack not set: {}; running with the default", why(errno)));
    }
  }
  if (settings.lock_memory) {
    if (::mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
      report.push_back("memory locked (mlockall)");
    } else {
      report.push_back(fmt::format("memory not locked: {}; running without", why(errno)));
    }
  }
  if (settings.fifo_priority) {
    sched_param param{};
    param.sched_priority = *settings.fifo_priority;
    if (::sched_setscheduler(0, SCHED_FIFO, &param) == 0) {
      report.push_back(fmt::format("real-time priority SCHED_FIFO {}", *settings.fifo_priority));
    } else {
      report.push_back(fmt::format("real-time priority SCHED_FIFO {} not set: {}; running with normal scheduling",
                                   *settings.fifo_priority, why(errno)));
    }
  }
  return report;
}

}  // namespace gpsemu::posix
