// An in-process transport::Output standing for a client on the other end of the line, for the
// pipeline tests: what the client "writes" (`input`) is handed to the sink at the next service(),
// and everything the emulator writes is kept, whole (`written`) and write by write (`sent`).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "transport/output.hpp"

namespace gpsemu::test {

class TalkingOutput final : public transport::Output {
 public:
  void service() override {
    client_wrote(input);
    input.clear();
  }
  [[nodiscard]] std::string describe() const override { return "talking"; }
  std::string input;               ///< what the client writes at the next service()
  std::string written;             ///< every byte written to it
  std::vector<std::string> sent;   ///< each write

 protected:
  transport::WriteStatus write_bytes(std::string_view bytes, std::string&) override {
    written += bytes;
    sent.emplace_back(bytes);
    return transport::WriteStatus::ok;
  }
};

}  // namespace gpsemu::test
