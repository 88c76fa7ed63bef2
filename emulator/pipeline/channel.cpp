#include "emulator/pipeline/channel.hpp"

#include <algorithm>
#include <utility>

#include "emulator/faults/garble.hpp"
#include "emulator/heading/rtcm3_base.hpp"
#include "emulator/pipeline/rtk_receiver.hpp"
#include "emulator/protocol/nmea_protocol.hpp"
#include "emulator/rtk/static_base_relpos.hpp"

namespace gpsemu {

Channel::Channel(const ChannelSettings& settings, UtcNs first_epoch)
    : settings_(settings), frame_(settings.origin), status_(settings.seed) {
  receiver_ = std::make_unique<Receiver>(frame_, settings_.receiver,
                                         noise::make_noise_model(settings_.noise, settings_.seed), first_epoch);
  protocols_.push_back(settings_.protocol ? settings_.protocol->make()
                                          : std::make_unique<protocol::NmeaProtocol>(settings_.format));
  protocol_ = protocols_.front().get();
  faults_.emplace(settings_.faults, first_epoch);  // without faults: a few compares an epoch
  rtk_ = std::make_unique<RtkReceiver>(settings_.rtk, settings_.rtcm);
  if (settings_.moving_base.role == heading::Role::rover) rover_.emplace(settings_.moving_base, settings_.seed);
  bytes_.reserve(1024);
}

Channel::~Channel() = default;

ReceiverEpoch Channel::step(UtcNs t) {
  source_->service();
  return step(t, source_->truth_at(t));
}

ReceiverEpoch Channel::step(UtcNs t, const std::optional<sources::Truth>& vehicle) {
  // The antenna's place on the vehicle (docs/heading.md): where this receiver's truth is.
  std::optional<sources::Truth> truth = vehicle;
  const heading::AntennaOffset& antenna = settings_.moving_base.antenna;
  const bool offset = antenna.forward_m != 0.0 || antenna.right_m != 0.0 || antenna.down_m != 0.0;
  if (offset && truth && truth->yaw_deg) {  // no rotation for an antenna at the reference point
    truth->position_m = truth->position_m + heading::offset_enu(antenna, *truth->yaw_deg,
                                                                truth->tilt.pitch_deg, truth->tilt.roll_deg);
  }
  last_step_ = t;
  // The epoch, built forward: the model's fix, then RTK and the relative position, then the faults;
  // then every protocol encodes it as it is.
  ReceiverEpoch epoch = receiver_->epoch_at(t, truth);  // made in place: no 2 KB copy an epoch
  nmea::Fix& fix = epoch.fix;
  bytes_.clear();
  const std::optional<Enu> truth_m = truth ? std::optional<Enu>(truth->position_m) : std::nullopt;
  last_truth_m_ = truth_m;
  rtk_->service();
  rtk_->apply(t, fix, truth_m, frame_);  // corrections before faults: a forced quality or an outage wins
  if (rover_) {
    epoch.relative_position = rover_->at(t, truth, last_corrections_);  // a moving-base rover's baseline
  } else if (rtk_->counts().messages > 0) {
    epoch.relative_position = rtk::static_base_relpos(rtk_->status(), rtk_->base(), fix);  // a fixed base's rover
  }
  const faults::EpochEffect effect = faults_->apply(t, epoch, truth_m, frame_);
  silent_ = effect.silent;
  if (effect.reboot_cold_start_s) reboot(t, *effect.reboot_cold_start_s);
  if (silent_) {
    ++stats_.epochs_silent;
  } else {
    // Last, from the fix as the faults left it: run time, TTFF, time validity and the clock (a
    // silent receiver reports nothing; after a reboot its run time counts from its first word).
    epoch.status = status_.at(fix);
    if (!fix.has_fix()) ++stats_.epochs_without_fix;
    for (const auto& p : protocols_) p->encode(epoch, bytes_);
    if (settings_.moving_base.role == heading::Role::moving_base) bytes_ += heading::base_rtcm3_epoch(fix, 0);
  }
  apply_byte_faults(t, effect);
  return epoch;
}

void Channel::cold_start(UtcNs t) {
  receiver_->restart(t);
  rtk_->restart();
  status_.restart();
}

void Channel::reboot(UtcNs t, double cold_start_s) {
  receiver_->restart(t, cold_start_s);
  rtk_->restart();
  status_.restart();
  protocol_->reset(protocol::ResetKind::hardware_cold);
}

void Channel::apply_byte_faults(UtcNs t, const faults::EpochEffect& effect) {
  const auto t_ns = static_cast<std::uint64_t>(t.time_since_epoch().count());
  if (effect.garble_rate > 0.0 && !bytes_.empty()) {
    const faults::GarbleCounts c = faults::garble(bytes_, effect.garble_rate, faults::mix_seed(settings_.seed, t_ns));
    stats_.epochs_garbled += (c.flipped + c.truncated) > 0;
    stats_.units_flipped += c.flipped;
    stats_.units_truncated += c.truncated;
  }
  if (effect.delay_ms <= 0.0 && effect.jitter_ms <= 0.0 && delayed_.empty()) return;
  // The jitter's draw from the seed and the epoch: the same run gives the same delays.
  const double draw = static_cast<double>(faults::mix_seed(settings_.seed ^ 0x6c6174656e6379ULL, t_ns) >> 11) * 0x1.0p-53;
  const double delay_ms = effect.delay_ms + effect.jitter_ms * draw;
  if (delay_ms > 0.0) ++stats_.epochs_delayed;
  // Never before an epoch held back earlier: a slow receiver's bytes still leave in order.
  UtcNs release = t + std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double, std::milli>(delay_ms));
  if (!delayed_.empty()) release = std::max(release, delayed_.back().release);
  if (!bytes_.empty()) delayed_.push_back({release, std::move(bytes_)});
  bytes_.clear();
  bytes_ = take_delayed(t);
}

std::string_view Channel::take_delayed(UtcNs t) {
  released_.clear();
  while (!delayed_.empty() && delayed_.front().release <= t) {
    released_ += delayed_.front().bytes;
    delayed_.pop_front();
  }
  return released_;
}

bool Channel::reads_input() const {
  for (const auto& p : protocols_) {
    if (p->reads_client_input()) return true;
  }
  return false;
}

void Channel::client_wrote(std::string_view bytes, ClientId client) {
  for (const auto& p : protocols_) p->client_wrote(bytes, client);
  // RTCM3 the client interleaves with the protocol (its input's reader splits and checks it): a
  // base station's corrections drive the RTK state; a rover's moving base, forwarded by the
  // autopilot, is recognised by its 4072.0 (reference station PVT) and makes the baseline valid.
  for (const rtk::Rtcm3Message& m : protocol_->take_corrections()) {
    rtk_->received(m);
    if (rover_ && m.valid && m.type == 4072 && m.subtype == 0) {
      ++moving_base_frames_;
      if (last_step_) last_corrections_ = last_step_;
    }
  }
}

std::string Channel::take_reply(ClientId client) {
  std::string reply;
  for (const auto& p : protocols_) reply += p->take_reply(client);
  if (silent_ && !reply.empty()) {  // a silent receiver writes nothing, answers included
    stats_.replies_withheld_bytes += reply.size();
    reply.clear();
  }
  return reply;
}

void Channel::client_left(ClientId client) {
  for (const auto& p : protocols_) p->client_left(client);
}

}  // namespace gpsemu
