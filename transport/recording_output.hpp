// A recording fake of the transport interface for tests: keeps every epoch it was given and can
// be told to drop or fail the next writes.
#pragma once

#include <string>
#include <vector>

#include "transport/output.hpp"

namespace gpsemu::transport {

class RecordingOutput final : public Output {
 public:
  std::vector<std::string> epochs;      ///< every epoch written, in order
  WriteStatus next_status = WriteStatus::ok;

  [[nodiscard]] std::string describe() const override { return "recording"; }

 protected:
  WriteStatus write_bytes(std::string_view bytes, std::string& error_text) override {
    if (next_status != WriteStatus::ok) {
      error_text = "recording fake told to refuse";
      return next_status;
    }
    epochs.emplace_back(bytes);
    return WriteStatus::ok;
  }
};

}  // namespace gpsemu::transport
