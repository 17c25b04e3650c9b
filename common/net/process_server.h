// What every server process's main does the same way: server options from its section of
// the lab configuration, the port it got written for a supervisor or a test (--port-file),
// and a clean stop on SIGINT or SIGTERM.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "common/config/process_options.h"
#include "common/net/server.h"

namespace igms::net {

// The keys ServerOptionsFor reads besides the common ones (config::CommonKeys): max_frame_bytes.
const config::Keys& ServerKeys();

// name, bind address, port (default_port when the configuration has none) and token from
// what ParseProcessOptions read (process.entry, process.lab), and max_frame_bytes.
ServerOptions ServerOptionsFor(const config::ProcessOptions& process, std::uint16_t default_port);

// When the process was given --port-file PATH, writes the port there atomically (a reader
// never sees a half-written file).
void WritePortFile(const config::ProcessOptions& process, std::uint16_t port);

// Calls stop() once on SIGINT or SIGTERM, on the io_context's thread. Keep the returned
// signal set alive as long as the handler should be.
std::unique_ptr<boost::asio::signal_set> StopOnSignal(boost::asio::io_context& io,
                                                      std::function<void()> stop);

}  // namespace igms::net
