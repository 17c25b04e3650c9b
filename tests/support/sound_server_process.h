// A real igms-sound-server process for tests and benchmarks, and a client that speaks its
// requests over loopback TCP. Header-only: its users link igms_sound.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "common/net/client.h"
#include "igms/sound.pb.h"
#include "sound_server/sound_service.h"
#include "tests/support/child_process.h"
#include "tests/support/wait.h"

namespace igms::sound::testing {

// igms-sound-server on an ephemeral port (--port 0) with `args`, as a real child process.
class ServerProcess : public igms::testing::ChildProcess {
 public:
  explicit ServerProcess(const std::vector<std::string>& args)
      : ChildProcess("igms-sound-server", WithPort(args)) {}

 private:
  static std::vector<std::string> WithPort(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {"--port", "0"};
    argv.insert(argv.end(), args.begin(), args.end());
    return argv;
  }
};

// A client of the sound server with its own network thread.
class SoundClient {
 public:
  explicit SoundClient(uint16_t port) : client_(port, "sound-test") {
    client_->WaitConnected(std::chrono::seconds(5));
  }
  template <class Resp, class Req>
  net::Result<Resp> Call(const std::string& method, const Req& req) {
    return client_->CallSync<Resp>(method, req, std::chrono::seconds(5));
  }
  net::Result<PlayResponse> Play(const std::string& key, Priority priority = PRIORITY_NORMAL,
                                 std::optional<float> volume = std::nullopt) {
    PlayRequest req;
    req.set_key(key);
    req.set_priority(priority);
    if (volume) req.set_volume(*volume);
    return Call<PlayResponse>(kPlayMethod, req);
  }
  net::Result<StatusResponse> Status() {
    return Call<StatusResponse>(kStatusMethod, StatusRequest());
  }
  // Waits until nothing plays or waits; false if that does not happen in time.
  bool WaitIdle(std::chrono::milliseconds limit = std::chrono::seconds(10)) {
    return igms::testing::WaitUntil(
        [&] {
          net::Result<StatusResponse> s = Status();
          return s.ok() && s.value.plays_size() == 0;
        },
        limit, std::chrono::milliseconds(5));
  }

 private:
  igms::testing::TestClient client_;
};

}  // namespace igms::sound::testing
