// An in-process transport::Output standing for a client on the other end of the line, for the
// pipeline tests: what the client "writes" (`input`) is handed to the sink at the next service(),
// and everything the emulator writes is kept, whole (`written`) and write by write (`sent`);
// add_talking_output() adds one to a Sink as a receiver's output.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <cstddef>
#include <memory>

#include "emulator/pipeline/sink.hpp"
#include "transport/output.hpp"

namespace gpsemu::test {

class TalkingOutput final : public transport::Output {
 public:
  void service() override {
    client_wrote(input, client_id);
    input.clear();
  }
  [[nodiscard]] std::string describe() const override { return "talking"; }
  std::string input;               ///< what the client writes at the next service()
  transport::ClientId client_id = transport::new_client_id();  ///< who writes it
  std::string written;             ///< every byte written to it
  std::vector<std::string> sent;   ///< each write

 protected:
  transport::WriteStatus write_bytes(std::string_view bytes, std::string&) override {
    written += bytes;
    sent.emplace_back(bytes);
    return transport::WriteStatus::ok;
  }
};

/// A TalkingOutput added to `sink` as one receiver's only output: the client and that receiver's
/// index in the sink.
struct TalkingClient {
  TalkingOutput* client;
  std::size_t index;
};
inline TalkingClient add_talking_output(Sink& sink) {
  std::vector<std::unique_ptr<transport::Output>> outputs;
  auto talking = std::make_unique<TalkingOutput>();
  TalkingOutput* client = talking.get();
  outputs.push_back(std::move(talking));
  return {client, sink.add(std::move(outputs))};
}

}  // namespace gpsemu::test
