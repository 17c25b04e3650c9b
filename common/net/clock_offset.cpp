#include "common/net/clock_offset.h"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <utility>

#include "common/base/clock.h"
#include "igms/common.pb.h"

namespace igms::net {

std::string ClockOffset::Describe() const {
  char text[128];
  std::snprintf(text, sizeof text, "%+.3f ms (within \u00b1%.3f ms, best of %d ping%s)",
                static_cast<double>(offset_ns) / 1e6, static_cast<double>(bound_ns()) / 1e6,
                samples, samples == 1 ? "" : "s");
  return text;
}

std::optional<ClockOffset> EstimateClockOffset(const std::vector<ClockSample>& samples) {
  std::optional<ClockOffset> best;
  int usable = 0;
  for (const ClockSample& s : samples) {
    if (s.server_unix_ns == 0 || s.receive_unix_ns < s.send_unix_ns) continue;
    ++usable;
    const std::int64_t round_trip = s.receive_unix_ns - s.send_unix_ns;
    if (best && best->round_trip_ns <= round_trip) continue;
    // t0 + (t3 - t0) / 2 rather than (t0 + t3) / 2: the sum of two Unix ns stamps is near
    // the int64 limit.
    best = ClockOffset{s.server_unix_ns - (s.send_unix_ns + round_trip / 2), round_trip, 0};
  }
  if (best) best->samples = usable;
  return best;
}

std::optional<ClockOffset> MeasureClockOffset(Client& client, int pings,
                                              std::chrono::milliseconds timeout,
                                              std::string* error) {
  std::vector<ClockSample> samples;
  for (int i = 0; i < pings; ++i) {
    ClockSample s;
    s.send_unix_ns = UnixNs();
    auto r = client.CallSync<PingResponse>("igms.Server.Ping", PingRequest(), timeout);
    s.receive_unix_ns = UnixNs();
    if (!r.ok()) {
      *error = "ping: " + r.status.ToString();
      return std::nullopt;
    }
    s.server_unix_ns = r.value.server_unix_ns();
    samples.push_back(s);
  }
  auto estimate = EstimateClockOffset(samples);
  if (!estimate) *error = "the server's pings carry no time (a server older than this client)";
  return estimate;
}

namespace {
struct AsyncPings {
  Client* client;
  int pings;
  std::chrono::milliseconds timeout;
  ClockOffsetDone done;
  std::vector<ClockSample> samples;

  static void Next(std::shared_ptr<AsyncPings> self) {
    if (static_cast<int>(self->samples.size()) >= self->pings) {
      auto estimate = EstimateClockOffset(self->samples);
      self->done(
          estimate,
          estimate ? "" : "the server's pings carry no time (a server older than this client)");
      return;
    }
    const std::int64_t sent = UnixNs();
    Client* client = self->client;
    const auto timeout = self->timeout;
    client->Call<PingResponse>(
        "igms.Server.Ping", PingRequest(), timeout,
        [self = std::move(self), sent](const Result<PingResponse>& r) mutable {
          const std::int64_t received = UnixNs();
          if (!r.ok()) {
            self->done(std::nullopt, "ping: " + r.status.ToString());
            return;
          }
          self->samples.push_back({sent, r.value.server_unix_ns(), received});
          Next(std::move(self));
        });
  }
};
}  // namespace

void MeasureClockOffsetAsync(Client& client, int pings, std::chrono::milliseconds timeout,
                             ClockOffsetDone done) {
  auto state = std::make_shared<AsyncPings>();
  state->client = &client;
  state->pings = pings > 0 ? pings : 1;
  state->timeout = timeout;
  state->done = std::move(done);
  AsyncPings::Next(std::move(state));
}

}  // namespace igms::net
