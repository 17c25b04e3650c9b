#include "common/net/process_server.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <fstream>

namespace igms::net {

const config::Keys& ServerKeys() {
  static const config::Keys keys = [] {
    config::Keys k;
    k.Add("max_frame_bytes", config::KeyType::kInt, std::to_string(ServerOptions().max_frame_bytes),
          "the largest request accepted, in bytes");
    return k;
  }();
  return keys;
}

ServerOptions ServerOptionsFor(const config::ProcessOptions& process, std::uint16_t default_port) {
  ServerOptions options;
  options.name = process.name;
  options.bind_address = process.BindAddress();
  options.port = process.Port(default_port);
  options.token = process.Token();
  options.max_frame_bytes = process.Get<std::size_t>("max_frame_bytes", options.max_frame_bytes);
  return options;
}

void WritePortFile(const config::ProcessOptions& process, std::uint16_t port) {
  if (!process.flags.count("port-file")) return;
  const std::string path = process.flags["port-file"].as<std::string>();
  std::ofstream(path + ".tmp") << port << "\n";
  std::rename((path + ".tmp").c_str(), path.c_str());
}

std::unique_ptr<boost::asio::signal_set> StopOnSignal(boost::asio::io_context& io,
                                                      std::function<void()> stop) {
  auto signals = std::make_unique<boost::asio::signal_set>(io, SIGINT, SIGTERM);
  signals->async_wait([stop = std::move(stop)](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    spdlog::info("signal {}: shutting down", signal);
    stop();
  });
  return signals;
}

}  // namespace igms::net
