#include "common/net/process_server.h"

#include <netdb.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace igms::net {

namespace {

// The keys ServerOptionsFor reads, bound to `options` (ServerKeys() declares them unbound).
config::Keys BoundServerKeys(ServerOptions* options) {
  config::Keys k;
  k.Bind("max_frame_bytes", &options->max_frame_bytes, "the largest request accepted, in bytes");
  return k;
}

}  // namespace

const config::Keys& ServerKeys() {
  // Merged into every server's keys: declarations only, so reading them there writes nowhere.
  static const config::Keys keys = [] {
    ServerOptions defaults;
    const config::Keys bound = BoundServerKeys(&defaults);
    config::Keys k;
    for (const auto& spec : bound.specs()) {
      k.Add(spec.key, spec.type, spec.default_value, spec.help);
    }
    return k;
  }();
  return keys;
}

namespace {

// Where a server listens: its `bind`, else its `host`, the address the others reach it at
// (a server whose host is another workstation's address and that listened on loopback could
// not be reached). A host name (compose's service names, localhost) is resolved here.
std::string ListenAddress(const config::ProcessOptions& process) {
  if (!process.entry.bind.empty()) return process.entry.bind;
  const std::string& host = process.entry.host;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICHOST;
  addrinfo* found = nullptr;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &found) == 0) {
    ::freeaddrinfo(found);
    return host;
  }
  hints.ai_flags = 0;
  hints.ai_family = AF_INET;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr) {
    throw std::runtime_error(process.name + ": cannot resolve its host '" + host +
                             "' to listen on (set processes." + process.name + ".bind)");
  }
  char text[NI_MAXHOST] = {};
  ::getnameinfo(found->ai_addr, found->ai_addrlen, text, sizeof text, nullptr, 0, NI_NUMERICHOST);
  ::freeaddrinfo(found);
  return text;
}

}  // namespace

ServerOptions ServerOptionsFor(const config::ProcessOptions& process, std::uint16_t default_port) {
  ServerOptions options;
  options.name = process.name;
  options.bind_address = ListenAddress(process);
  options.port = process.Port(default_port);
  options.token = process.lab.token;
  BoundServerKeys(&options).Read(process);
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
