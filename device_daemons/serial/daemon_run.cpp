#include <spdlog/spdlog.h>

#include "common/config/exit_codes.h"
#include "common/net/process_server.h"
#include "device_daemons/serial/daemon_base.h"

namespace igms::devices {

int RunDaemonProcess(boost::asio::io_context& io, const std::function<bool(std::string*)>& start,
                     const std::function<void()>& stop) {
  std::string error;
  if (!start(&error)) {
    spdlog::error("{}", error);
    return kExitFailure;
  }
  const auto signals = net::StopOnSignal(io, [&] {
    stop();
    io.stop();
  });
  // One thread: the drivers and the server share it, so neither needs locks.
  io.run();
  return kExitOk;
}

}  // namespace igms::devices
