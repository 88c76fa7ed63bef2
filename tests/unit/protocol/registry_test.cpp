// Which protocol a receiver speaks (protocol/registry.hpp): plain NMEA unless a u-blox port is
// asked for (--protocol ubx or nmea+ubx) or a u-blox --receiver is in its factory state; what the
// u-blox writes at start (UBX alone, or NMEA+UBX); a serial output without a baud gets the model's
// factory baud only in the factory state; the start-up line budget of the spec is the made
// protocol's at start; and plain NMEA asks for nothing.
#include <gtest/gtest.h>

#include "emulator/config/config.hpp"
#include "emulator/config/receiver_config.hpp"
#include "emulator/protocol/nmea_protocol.hpp"
#include "emulator/protocol/registry.hpp"
#include "nmea/line_budget.hpp"
#include "transport/posix/fd.hpp"

namespace gpsemu::protocol {
namespace {
namespace registry_test {

Config config_of(const RawOptions& cli) { return build_config(std::nullopt, cli); }

struct Chosen {
  std::shared_ptr<const ProtocolSpec> spec;
  std::unique_ptr<ReceiverProtocol> made;
  std::size_t spec_widest = 0;
  std::size_t made_widest = 0;
  int baud = 0;
};

Chosen choose(const RawOptions& cli) {
  const Config c = config_of(cli);
  const ReceiverOptions options = receiver_options(c.receiver());
  Chosen out;
  out.spec = protocol_for(c.receiver(), options, c.timeline, posix::replace_file);
  out.made = out.spec->make();
  out.spec_widest = out.spec->widest_epoch_bytes(resolve_geometry(options));
  out.made_widest = out.made->widest_epoch_bytes(resolve_geometry(options));
  out.baud = factory_baud(c.receiver());
  return out;
}

TEST(ProtocolRegistry, PlainNmeaUnlessAUbloxPortIsAskedFor) {
  const Chosen nmea = choose({{"protocol", {"nmea"}}});
  EXPECT_EQ(nmea.made->name(), "NMEA");
  EXPECT_EQ(nmea.made->written(), "NMEA");
  EXPECT_TRUE(nmea.made->receiver_name().empty());
  EXPECT_FALSE(nmea.made->reads_client_input());
  EXPECT_EQ(nmea.baud, 0);
  EXPECT_EQ(nmea.spec_widest, nmea.made_widest);
  EXPECT_GT(nmea.made_widest, 0u);

  const Chosen m9n_nmea = choose({{"receiver", {"ublox-m9n"}}, {"protocol", {"nmea"}}});
  EXPECT_EQ(m9n_nmea.made->name(), "NMEA") << "--protocol nmea given: no u-blox port";
  EXPECT_EQ(m9n_nmea.baud, 0);
}

TEST(ProtocolRegistry, AUbloxPortForProtocolUbxOrAModelInItsFactoryState) {
  const Chosen ubx = choose({{"receiver", {"ublox-f9p"}}, {"protocol", {"ubx"}}});
  EXPECT_EQ(ubx.made->name(), "u-blox");
  EXPECT_EQ(ubx.made->receiver_name(), "u-blox ublox-f9p");
  EXPECT_EQ(ubx.made->written(), "UBX") << "no --sentences: NMEA off";
  EXPECT_TRUE(ubx.made->reads_client_input());
  EXPECT_TRUE(ubx.made->has_tx_buffer());
  EXPECT_EQ(ubx.baud, 0) << "--protocol given: not the factory state";
  EXPECT_EQ(ubx.spec_widest, ubx.made_widest);

  const Chosen factory = choose({{"receiver", {"ublox-m9n"}}});
  EXPECT_EQ(factory.made->name(), "u-blox");
  EXPECT_EQ(factory.made->written(), "NMEA+UBX");
  EXPECT_EQ(factory.baud, 38400) << "a NEO-M9N's UART1 after a factory reset";
  EXPECT_EQ(factory.spec_widest, factory.made_widest);

  EXPECT_EQ(choose({{"protocol", {"nmea+ubx"}}}).made->written(), "NMEA+UBX");
}

TEST(NmeaProtocol, WritesTheSentencesAndAsksForNothing) {
  nmea::FormatOptions format;
  NmeaProtocol nmea(format);
  ReceiverEpoch epoch;
  epoch.fix.quality = nmea::FixQuality::gps;
  epoch.rf.jamming_state = 3;  // what NMEA has no sentence for is left out
  epoch.relative_position = RelativePosition{.north_m = 1.0};
  const nmea::Fix& fix = epoch.fix;
  std::string out;
  nmea.encode(epoch, out);
  std::string expected;
  nmea::SatelliteTextMemo memo;
  nmea::append_epoch(fix, format, expected, memo);
  EXPECT_EQ(out, expected);
  nmea.client_wrote("$PUBX,40,GGA,0,0,0,0*5A\r\n", 1);
  EXPECT_TRUE(nmea.take_reply(1).empty());
  EXPECT_TRUE(nmea.take_effects().empty());
  EXPECT_TRUE(nmea.take_corrections().empty());
  EXPECT_FALSE(nmea.period_change_pending());
  EXPECT_FALSE(nmea.has_tx_buffer());
  EXPECT_TRUE(nmea.client_input_summary("").empty());
}

}  // namespace registry_test
}  // namespace
}  // namespace gpsemu::protocol
