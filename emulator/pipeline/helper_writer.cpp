#include "emulator/pipeline/helper_writer.hpp"

#include "transport/posix/wait.hpp"

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

void HelperWriter::post(UtcNs write_at, std::size_t first, std::size_t from, std::size_t to, UtcNs latest) {
  {
    const std::lock_guard lock(mutex_);
    job_ = Job{write_at, first, from, to, latest};
    busy_ = true;
  }
  wake_.notify_all();
}

void HelperWriter::wait_done() {
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return !busy_; });
}

void HelperWriter::loop() {
  posix::Waiter waiter;  // this thread's own timer: nothing to poll
  const std::atomic<bool> never{false};
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return quit_ || job_.has_value(); });
    if (quit_) return;
    const Job job = *job_;
    job_.reset();
    lock.unlock();
    waiter.sleep_until(job.write_at, never);
    if (posix::wall_clock_now() <= job.latest) write_(job.first, job.from, job.to);
    lock.lock();
    busy_ = false;
    done_.notify_all();
  }
}

}  // namespace gpsemu
