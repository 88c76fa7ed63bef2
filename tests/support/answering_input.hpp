// Test support: a transport::ClientInput standing for a receiver that answers every write with
// one fixed answer, and remembers which client wrote and which left (the transport tests of the
// per-client answer path).
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "transport/output.hpp"

namespace gpsemu::test {

class AnsweringInput final : public transport::ClientInput {
 public:
  explicit AnsweringInput(std::string answer) : answer_(std::move(answer)) {}
  void client_wrote(std::string_view /*bytes*/, transport::ClientId client) override {
    writers.push_back(client);
    pending_ = answer_;
  }
  std::string take_reply(transport::ClientId /*client*/) override { return std::exchange(pending_, std::string{}); }
  void client_left(transport::ClientId client) override { left.push_back(client); }

  std::vector<transport::ClientId> writers;  ///< who wrote, one entry a write
  std::vector<transport::ClientId> left;     ///< who left, in order

 private:
  std::string answer_, pending_;
};

}  // namespace gpsemu::test
