#include <spdlog/spdlog.h>

#include <boost/asio/signal_set.hpp>
#include <csignal>

#include "device_daemons/serial/daemon_base.h"

namespace igms::devices {

int RunDaemonProcess(boost::asio::io_context& io, const std::function<bool(std::string*)>& start,
                     const std::function<void()>& stop) {
  std::string error;
  if (!start(&error)) {
    spdlog::error("{}", error);
    return 1;
  }
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int) {
    if (ec) return;
    spdlog::info("stopping");
    stop();
    io.stop();
  });
  // One thread: the drivers and the server share it, so neither needs locks.
  io.run();
  return 0;
}

}  // namespace igms::devices
