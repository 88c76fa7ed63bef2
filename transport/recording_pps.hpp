// A recording fake of the PPS interface for tests: keeps every edge as (wall-clock reading at the
// call, level driven), so a test can measure each edge against the UTC second and order it
// against the NMEA writes. Can be told to fail.
#pragma once

#include <vector>

#include "transport/posix/wall_clock.hpp"
#include "transport/pps.hpp"

namespace gpsemu::transport {

class RecordingPps final : public PpsLine {
 public:
  struct Edge {
    PpsTime time{};      ///< CLOCK_REALTIME read when set() drove the line
    bool level = false;  ///< the level driven (polarity applied): true high / asserted
  };

  explicit RecordingPps(PpsPolarity polarity = PpsPolarity::active_high) : PpsLine(polarity) {}

  std::vector<Edge> edges;  ///< every edge driven, in order
  bool fail = false;        ///< refuse the next edges (as a lost device would)

  [[nodiscard]] std::string describe() const override { return "recording"; }

  /// CLOCK_REALTIME now, as the fake reads it.
  [[nodiscard]] static PpsTime now() { return posix::wall_clock_now(); }

 protected:
  bool drive(bool level, std::string& error_text) override {
    if (fail) {
      error_text = "recording fake told to fail";
      return false;
    }
    edges.push_back({now(), level});
    return true;
  }
};

}  // namespace gpsemu::transport
