#include "emulator/pipeline/helper_writer.hpp"

#include <time.h>

#include <cerrno>

namespace gpsemu {

HelperWriter::HelperWriter(WriteFn write) : write_(std::move(write)), thread_([this] { loop(); }) {}

HelperWriter::~HelperWriter() {
  wait_done();
  {
    const std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void HelperWriter::post(UtcNs write_at, std::size_t first, std::size_t from, std::size_t to) {
  {
    const std::lock_guard lock(mutex_);
    job_ = Job{write_at, first, from, to};
    busy_ = true;
  }
  wake_.notify_all();
}

void HelperWriter::wait_done() {
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return !busy_; });
}

void HelperWriter::loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return quit_ || job_.has_value(); });
    if (quit_) return;
    const Job job = *job_;
    job_.reset();
    lock.unlock();
    const std::int64_t ns = job.write_at.time_since_epoch().count();
    const timespec ts{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
    while (clock_nanosleep(CLOCK_REALTIME, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    write_(job.first, job.from, job.to);
    lock.lock();
    busy_ = false;
    done_.notify_all();
  }
}

}  // namespace gpsemu
