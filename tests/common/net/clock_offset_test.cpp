// The clock offset estimate: on made-up stamps (a known offset, uneven legs, the shortest
// round trip kept) and against a real server on loopback, where the two clocks are one.
#include "common/net/clock_offset.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <future>
#include <optional>

#include "common/net/server.h"
#include "tests/support/io_thread.h"

namespace igms::net {
namespace {

using namespace std::chrono_literals;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kNow = 1'780'000'000'000'000'000;  // a Unix ns stamp of 2026

TEST(ClockOffset, FromTheShortestRoundTripWithinHalfOfIt) {
  // The server's clock is 40 ms ahead. First ping: 2 ms out, 8 ms back; second: 1 ms each way.
  const std::vector<ClockSample> samples = {
      {kNow, kNow + 2 * kMs + 40 * kMs, kNow + 10 * kMs},
      {kNow + 100 * kMs, kNow + 101 * kMs + 40 * kMs, kNow + 102 * kMs},
      {kNow + 200 * kMs, 0, kNow + 201 * kMs},  // an old server: no stamp, not used
  };
  const auto offset = EstimateClockOffset(samples);
  ASSERT_TRUE(offset);
  EXPECT_EQ(offset->offset_ns, 40 * kMs);  // even legs: exact
  EXPECT_EQ(offset->round_trip_ns, 2 * kMs);
  EXPECT_EQ(offset->samples, 2);
  EXPECT_EQ(offset->Describe(), "+40.000 ms (within \u00b11.000 ms, best of 2 pings)");

  // The uneven first ping alone: wrong by 3 ms, within its bound of 5.
  const auto uneven = EstimateClockOffset({samples[0]});
  ASSERT_TRUE(uneven);
  EXPECT_EQ(uneven->offset_ns, 37 * kMs);
  EXPECT_LE(std::llabs(uneven->offset_ns - 40 * kMs), uneven->bound_ns());

  // A stamp of the server's clock, put on this host's: 40 ms earlier.
  EXPECT_EQ(offset->ToLocalNs(kNow + 40 * kMs), kNow);

  EXPECT_FALSE(EstimateClockOffset({samples[2]}));
  EXPECT_FALSE(EstimateClockOffset({}));
}

// A server and a client of it on loopback: one clock on both ends.
class OnLoopback : public ::testing::Test {
 protected:
  void SetUp() override {
    server.Start();
    ClientOptions o;
    o.port = server.port();
    client.emplace(io.io(), o);
    client->Start();
  }
  void TearDown() override {
    if (client) client->Stop();
    server.Stop();
  }
  igms::testing::IoThread io;
  Server server{io.io(), ServerOptions{}};
  std::optional<Client> client;
};

TEST_F(OnLoopback, TheOffsetIsWithinHalfTheRoundTrip) {
  Client& client = *this->client;
  std::string error;
  const auto offset = MeasureClockOffset(client, 5, 2000ms, &error);
  ASSERT_TRUE(offset) << error;
  EXPECT_EQ(offset->samples, 5);
  EXPECT_GT(offset->round_trip_ns, 0);
  // One clock: the server's stamp lies between the send and the receive.
  EXPECT_LE(std::llabs(offset->offset_ns), offset->bound_ns() + 1)
      << offset->Describe();  // +1: rounding
  EXPECT_LT(std::llabs(offset->offset_ns), kClockOffsetLimit.count() * kMs);
}

// The form a client's own network thread uses (the window's live video): the pings chained
// from their callbacks, the estimate handed over at the end; a stopped client ends it.
TEST_F(OnLoopback, MeasuredWithoutBlockingTheNetworkThread) {
  Client& client = *this->client;
  std::promise<std::pair<std::optional<ClockOffset>, std::string>> got;
  MeasureClockOffsetAsync(client, 4, 2000ms,
                          [&](std::optional<ClockOffset> offset, const std::string& error) {
                            got.set_value({offset, error});
                          });
  auto future = got.get_future();
  ASSERT_EQ(future.wait_for(10s), std::future_status::ready);
  const auto [offset, error] = future.get();
  ASSERT_TRUE(offset) << error;
  EXPECT_EQ(offset->samples, 4);
  EXPECT_LE(std::llabs(offset->offset_ns), offset->bound_ns() + 1) << offset->Describe();

  // No server: the first ping fails and says why.
  server.Stop();
  client.Stop();
  std::promise<std::string> failed;
  MeasureClockOffsetAsync(client, 4, 500ms,
                          [&](std::optional<ClockOffset> offset, const std::string& error) {
                            failed.set_value(offset ? "" : error);
                          });
  auto why = failed.get_future();
  ASSERT_EQ(why.wait_for(10s), std::future_status::ready);
  EXPECT_NE(why.get().find("ping: "), std::string::npos);
}

}  // namespace
}  // namespace igms::net
