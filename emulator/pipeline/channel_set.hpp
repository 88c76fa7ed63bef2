// The emulator's producer for the one epoch loop: every receiver channel of a run (one, or a
// fleet), each on its own schedule (receiver_schedule.hpp: the run's grid, or the solution period
// its protocol's client asked for). The loop's timeline is their merge: one epoch a distinct time,
// and only the receivers due at that time send. A receiver whose protocol has a TX buffer (a
// u-blox) on a serial line sends what the line carries in its period (protocol_effects.hpp). The
// run ends at the time --duration gives, whatever the receivers' rates: when no receiver has an
// epoch left before the end (a client asked for one solution per 100 minutes), the last time of
// the run's grid is an idle
// epoch, no receiver due, so the loop keeps the ports open and answering until then.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "emulator/pipeline/channel.hpp"
#include "emulator/pipeline/epoch_loop.hpp"
#include "emulator/pipeline/receiver_schedule.hpp"
#include "emulator/pipeline/sink.hpp"
#include "emulator/pipeline/timeline.hpp"
#include "emulator/pipeline/protocol_effects.hpp"

namespace gpsemu {

/// Another input the loop services between epochs, beside the receivers' pose sources (the control
/// socket, control_socket.hpp).
class LoopInput {
 public:
  virtual ~LoopInput() = default;
  virtual void fds(std::vector<int>& out) const = 0;
  virtual void service() = 0;
};

/// What a receiver's epoch was, for whoever shows it (the bench view, `gpsemu ctl PATH watch`:
/// emulator/ui/hub.hpp). Valid during the call only.
struct EpochView {
  std::size_t receiver = 0;
  UtcNs t{};
  const Channel& channel;
  const nmea::Fix& fix;  ///< as reported (faults applied)
  const std::vector<std::unique_ptr<transport::Output>>* outputs = nullptr;  ///< none before the sink is attached
  const ReceiverLine& line;
};

/// Told every receiver's epoch by the loop's thread, after its bytes are made; must not block.
class EpochObserver {
 public:
  virtual ~EpochObserver() = default;
  virtual void epoch(const EpochView& view) = 0;
};

class ChannelSet final : public EpochProducer {
 public:
  /// `epochs`: of the run's grid (--duration x --rate); empty: until stopped.
  ChannelSet(const Timeline& timeline, std::optional<std::int64_t> epochs);

  /// Adds a receiver, on the run's grid from its first epoch.
  void add(std::unique_ptr<Channel> channel);
  /// The receivers' outputs, once the sink has them (baud changes, serial lines).
  void attach(const Sink& sink);
  /// Called with the finest period of the receivers' schedules whenever a receiver's changes (the
  /// clock's lateness follows it).
  void on_finest_period(std::function<void(std::chrono::nanoseconds)> changed) { finest_changed_ = std::move(changed); }
  /// The shortest time between a receiver's epochs now.
  [[nodiscard]] std::chrono::nanoseconds finest_period() const;

  bool next_epoch(UtcNs& t) override;
  [[nodiscard]] bool any_due() const override { return any_due_; }
  [[nodiscard]] bool active(std::size_t i) const override {
    return receivers_[i].due && !receivers_[i].channel->ended();
  }
  std::string_view produce(std::size_t i, UtcNs t) override;
  void list_inputs(std::vector<int>& fds, std::vector<std::size_t>& owners) const override;
  void service_input(std::size_t i) override {
    if (i < receivers_.size()) {
      receivers_[i].channel->source()->service();
    } else if (i - receivers_.size() < extra_owner_.size()) {
      extra_[extra_owner_[i - receivers_.size()]]->service();
    }
  }
  /// Services `input` with the receivers' inputs (the control socket, the bench view's requests).
  void add_extra_input(LoopInput* input) {
    if (input) extra_.push_back(input);
  }
  /// Tells `observer` each receiver's epoch (may be null: nobody).
  void set_observer(EpochObserver* observer) { observer_ = observer; }
  void service_inputs() override;
  [[nodiscard]] std::optional<UtcNs> delayed_until(std::size_t i) const override {
    return receivers_[i].channel->delayed_until();
  }
  [[nodiscard]] std::string_view take_delayed(std::size_t i, UtcNs t) override {
    return receivers_[i].channel->take_delayed(t);
  }
  [[nodiscard]] bool reschedule_wanted() const override;
  void reschedule(UtcNs now) override;

  [[nodiscard]] std::size_t size() const { return receivers_.size(); }
  [[nodiscard]] Channel& channel(std::size_t i) const { return *receivers_[i].channel; }
  [[nodiscard]] const ReceiverLine& line(std::size_t i) const { return receivers_[i].line; }

 private:
  struct Receiver {
    std::unique_ptr<Channel> channel;  ///< not moved: a receiver refers to its frame
    ReceiverSchedule schedule;
    ReceiverSchedule previous;  ///< before next_epoch() advanced it (reschedule() puts it back)
    ReceiverLine line;
    bool due = false;  ///< has an epoch at the time next_epoch() returned
  };

  const Timeline& timeline_;
  UtcNs end_;  ///< the first time past the run
  UtcNs last_;  ///< the run's last epoch on its grid (--duration), or max
  UtcNs latest_{UtcNs::min()};  ///< the latest time next_epoch() returned
  bool any_due_ = true;  ///< a receiver has an epoch at that time
  std::vector<Receiver> receivers_;
  const Sink* sink_ = nullptr;
  std::function<void(std::chrono::nanoseconds)> finest_changed_;
  std::vector<LoopInput*> extra_;
  /// list_inputs(): the extra input of each extra descriptor (owner receivers_.size() + k).
  mutable std::vector<std::size_t> extra_owner_;
  EpochObserver* observer_ = nullptr;
};

}  // namespace gpsemu
