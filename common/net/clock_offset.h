// The offset between this host's wall clock and a server's, estimated from pings: the
// estimate of NTP (RFC 5905, section 8) with one server stamp. The client stamps its send
// (t0) and its receive (t3), the server its answer (t1, PingResponse.server_unix_ns):
//
//   offset = t1 - (t0 + t3) / 2     the server's clock minus this one's
//
// which is true within half the round trip (t3 - t0) / 2 however the delay splits between
// the two legs. Of several pings the one with the shortest round trip is kept, its bound
// being the tightest.
//
// Why it matters: stamps taken on different hosts are compared (a grab's capture time on the
// video host against the platform reading's time on the daemons' host; a stream message's
// send time against its receive time), so the hosts' clocks must agree to well within the
// readings' period.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/net/client.h"

namespace igms::net {

// The offset beyond which the lab's cross-host stamps mislead: half the platform's 50 Hz
// reading period, so a grab can still be paired with the right reading (docs/deploy.md).
inline constexpr std::chrono::milliseconds kClockOffsetLimit{10};

struct ClockSample {
  std::int64_t send_unix_ns = 0;     // t0, this host
  std::int64_t server_unix_ns = 0;   // t1, the server (0: a server too old to say)
  std::int64_t receive_unix_ns = 0;  // t3, this host
};

struct ClockOffset {
  std::int64_t offset_ns = 0;      // the server's clock minus this host's
  std::int64_t round_trip_ns = 0;  // of the sample kept; the offset is true within half of it
  int samples = 0;                 // usable samples among those given
  std::int64_t bound_ns() const { return round_trip_ns / 2; }
  // A stamp of the server's clock on this host's: what latencies across hosts subtract.
  std::int64_t ToLocalNs(std::int64_t server_unix_ns) const { return server_unix_ns - offset_ns; }
  // "+0.012 ms (within ±0.050 ms, best of 5 pings)"
  std::string Describe() const;
};

// The estimate from the sample with the shortest round trip; nullopt when no sample has a
// server stamp and a receive time after its send time.
std::optional<ClockOffset> EstimateClockOffset(const std::vector<ClockSample>& samples);

// Pings `client` (started, connected or connecting) `pings` times, one after the other, and
// estimates. nullopt with `error` set when a ping fails or the server sends no stamp.
std::optional<ClockOffset> MeasureClockOffset(Client& client, int pings,
                                              std::chrono::milliseconds timeout,
                                              std::string* error);

// The same without blocking, for a client's own network thread: the pings go one after the
// other from the callbacks, and `done` gets the estimate, or nullopt and why. `client` must
// outlive the pings (Stop() fails those in flight, which ends them).
using ClockOffsetDone = std::function<void(std::optional<ClockOffset>, const std::string& error)>;
void MeasureClockOffsetAsync(Client& client, int pings, std::chrono::milliseconds timeout,
                             ClockOffsetDone done);

}  // namespace igms::net
