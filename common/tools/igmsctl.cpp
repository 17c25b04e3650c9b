#include "common/tools/igmsctl.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/dynamic_message.h>
#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/program_options.hpp>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "common/base/clock.h"
#include "common/config/exit_codes.h"
#include "common/config/lab_config.h"
#include "common/config/process_options.h"
#include "common/log/log.h"
#include "common/net/client.h"
#include "common/net/clock_offset.h"
#include "common/stats/percentile.h"
#include "common/version/version.h"

namespace igms::tools {

namespace po = boost::program_options;
namespace pb = google::protobuf;
using namespace std::chrono_literals;

namespace {

constexpr const char* kUsage = R"(usage: igmsctl [OPTIONS] COMMAND [ARGS]

Commands:
  list                       every service, method and stream igmsctl knows
  describe METHOD            a method's request and response messages
  ping                       igms.Server.Ping: is the server there, who is it (its name,
                             program, protocol version, uptime and IGMS version); then
                             the server's clock offset from --pings pings (on stderr),
                             with a warning beyond --max-offset-ms
  call METHOD [JSON]         send one request, print the response as JSON
  subscribe METHOD [JSON]    print each stream message as one line of JSON; with --count
                             or --duration it stops and prints the rate and the latency
                             (send to receipt, the server's stamps put on this host's
                             clock with the offset --pings pings estimate first)

METHOD is a full name (igms.video.VideoService.Grab) or a unique suffix (VideoService.Grab,
Grab). JSON is the request in protobuf's JSON form ('{}' when omitted).
Exit status: 0 ok, 1 the server answered with an error, 2 bad input or no server.
)";

std::vector<std::string> ProtoFiles() {
  std::vector<std::string> files;
  std::stringstream ss(IGMS_PROTO_FILES);
  std::string f;
  while (std::getline(ss, f, ',')) files.push_back(f);
  return files;
}

std::vector<const pb::MethodDescriptor*> AllMethods() {
  std::vector<const pb::MethodDescriptor*> out;
  for (const auto& name : ProtoFiles()) {
    const pb::FileDescriptor* file = pb::DescriptorPool::generated_pool()->FindFileByName(name);
    if (!file) continue;
    for (int s = 0; s < file->service_count(); ++s) {
      for (int m = 0; m < file->service(s)->method_count(); ++m) {
        out.push_back(file->service(s)->method(m));
      }
    }
  }
  return out;
}

const pb::MethodDescriptor* FindMethod(const std::string& name, std::string* error) {
  std::vector<const pb::MethodDescriptor*> matches;
  for (const auto* m : AllMethods()) {
    const std::string& full = m->full_name();
    if (full == name) return m;
    if (full.size() > name.size() &&
        full.compare(full.size() - name.size(), name.size(), name) == 0 &&
        full[full.size() - name.size() - 1] == '.') {
      matches.push_back(m);
    }
  }
  if (matches.size() == 1) return matches[0];
  if (matches.empty()) {
    *error = "no method '" + name + "' (igmsctl list shows them all)";
  } else {
    *error = "'" + name + "' is ambiguous:";
    for (const auto* m : matches) *error += " " + m->full_name();
  }
  return nullptr;
}

std::unique_ptr<pb::Message> NewMessage(const pb::Descriptor* type) {
  const pb::Message* prototype = pb::MessageFactory::generated_factory()->GetPrototype(type);
  return std::unique_ptr<pb::Message>(prototype->New());
}

std::string ToJson(const pb::Message& m) {
  std::string out;
  pb::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  const auto status = pb::util::MessageToJsonString(m, &out, options);
  if (!status.ok()) return "{\"error\": \"cannot print as JSON\"}";
  return out;
}

std::string Describe(const pb::Descriptor* d) {
  std::string out = d->full_name() + " {";
  for (int i = 0; i < d->field_count(); ++i) {
    const auto* f = d->field(i);
    out += std::string(i ? ", " : " ") + (f->is_repeated() ? "repeated " : "") +
           (f->message_type() ? f->message_type()->full_name()
            : f->enum_type()  ? f->enum_type()->full_name()
                              : f->type_name()) +
           " " + f->name();
  }
  return out + " }";
}

std::atomic<bool> g_interrupted{false};

// After a ping: the server's clock against this host's (common/net/clock_offset.h), on
// stderr, so stdout stays the response's JSON. Only a warning when it is far off: the
// server is there, which is what ping answers.
void ReportClock(net::Client& client, const po::variables_map& vm) {
  std::string error;
  const auto offset = net::MeasureClockOffset(
      client, vm["pings"].as<int>(), std::chrono::milliseconds(vm["timeout"].as<int>()), &error);
  if (!offset) {
    std::cerr << "igmsctl: no clock offset: " << error << "\n";
    return;
  }
  std::cerr << "igmsctl: clock offset " << offset->Describe()
            << ", the server's clock minus this host's\n";
  const double limit_ms = vm["max-offset-ms"].as<double>();
  if (static_cast<double>(std::abs(offset->offset_ns)) / 1e6 > limit_ms) {
    std::cerr << "igmsctl: warning: the server's clock is off by more than " << limit_ms
              << " ms; stamps compared across hosts (capture and platform times, latencies) "
                 "are wrong by as much: synchronise the clocks (NTP or PTP)\n";
  }
}

// The options --help shows.
po::options_description VisibleOptions() {
  po::options_description opts("Options");
  opts.add_options()("help,h", "show this help")("version", "print the version and exit")(
      "host", po::value<std::string>()->default_value("127.0.0.1"), "server host")(
      "port,p", po::value<int>(), "server port")(
      "config", po::value<std::string>(), "lab configuration: take host, port and token from it")(
      "to", po::value<std::string>(), "with --config: the process to talk to (its name)")(
      "token", po::value<std::string>(), "the lab token, when the lab has one")(
      "as", po::value<std::string>()->default_value("igmsctl"),
      "with TLS: the certificate to present, by name (NAME.crt in the lab's folder)")(
      "certs", po::value<std::string>(),
      "TLS with the certificates of this folder (else the lab file's lab.tls and lab.certs)")(
      "timeout", po::value<int>()->default_value(5000), "per-request timeout, ms")(
      "take-control",
      "call: set the request's take_control (the platform obeys one client at a time)")(
      "count,n", po::value<long>()->default_value(0), "subscribe: stop after N messages")(
      "duration", po::value<double>()->default_value(0), "subscribe: stop after S seconds")(
      "quiet,q", "subscribe: print only the summary")("pings", po::value<int>()->default_value(5),
                                                      "ping: pings that estimate the clock offset")(
      "max-offset-ms", po::value<double>()->default_value(net::kClockOffsetLimit.count()),
      "ping: warn when the server's clock is off by more")(
      "max-frame", po::value<std::size_t>()->default_value(64u << 20),
      "largest frame accepted, bytes")("log-level", po::value<std::string>()->default_value("warn"),
                                       "igmsctl's own log level");
  return opts;
}

// The method a command names (ping: igms.Server.Ping), checked against the command: a
// stream only for subscribe. Null after saying why.
const pb::MethodDescriptor* CommandMethod(const std::string& command,
                                          const std::vector<std::string>& args) {
  std::string method_name = command == "ping" ? "igms.Server.Ping" : "";
  if (command == "call" || command == "subscribe" || command == "describe") {
    if (args.size() < 2) {
      std::cerr << "igmsctl: " << command << " needs a METHOD\n";
      return nullptr;
    }
    method_name = args[1];
  } else if (command != "ping") {
    std::cerr << "igmsctl: unknown command '" << command << "' (see igmsctl --help)\n";
    return nullptr;
  }
  std::string error;
  const pb::MethodDescriptor* method = FindMethod(method_name, &error);
  if (!method) {
    std::cerr << "igmsctl: " << error << "\n";
    return nullptr;
  }
  if (command == "subscribe" && !method->server_streaming()) {
    std::cerr << "igmsctl: " << method->full_name() << " is not a stream; use call\n";
    return nullptr;
  }
  if (command == "call" && method->server_streaming()) {
    std::cerr << "igmsctl: " << method->full_name() << " is a stream; use subscribe\n";
    return nullptr;
  }
  return method;
}

// The request from its JSON ('{}' when omitted), with --take-control set. Null after saying
// why.
std::unique_ptr<pb::Message> MakeRequest(const pb::MethodDescriptor* method,
                                         const std::vector<std::string>& args,
                                         const po::variables_map& vm) {
  auto request = NewMessage(method->input_type());
  const std::string json = args.size() > 2 ? args[2] : "{}";
  if (auto s = pb::util::JsonStringToMessage(json, request.get()); !s.ok()) {
    std::cerr << "igmsctl: the request is not a " << method->input_type()->full_name() << ": "
              << s.message() << "\n";
    return nullptr;
  }
  if (vm.count("take-control")) {
    const pb::FieldDescriptor* take = request->GetDescriptor()->FindFieldByName("take_control");
    if (!take || take->type() != pb::FieldDescriptor::TYPE_BOOL) {
      std::cerr << "igmsctl: --take-control: a " << method->input_type()->full_name()
                << " has no take_control\n";
      return nullptr;
    }
    request->GetReflection()->SetBool(request.get(), take, true);
  }
  return request;
}

// Where and how to connect: --host/--port, or the lab file's process --to, with its token and
// TLS. Nothing after saying why.
std::optional<net::ClientOptions> ConnectionOptions(const std::string& command,
                                                    const po::variables_map& vm) {
  net::ClientOptions co;
  co.name = "igmsctl";
  co.reconnect = command == "subscribe";
  co.max_frame_bytes = vm["max-frame"].as<std::size_t>();
  co.host = vm["host"].as<std::string>();
  const std::string as = vm["as"].as<std::string>();
  co.tls = net::TlsOptions{};  // plain unless the lab file or --certs says TLS
  if (vm.count("certs")) co.tls = net::TlsOptions::FromFolder(vm["certs"].as<std::string>(), as);
  try {
    if (vm.count("config")) {
      const auto config = config::LabConfig::Load(vm["config"].as<std::string>());
      const config::LabOptions lab = config::LabOptionsOf(config);
      co.token = lab.token;
      const config::LabSecurity security = config::SecurityOf(lab, config, as);
      if (security.tls && !vm.count("certs"))
        co.tls = net::TlsOptions::FromFolder(security.certs_dir, as);
      if (!vm.count("to")) {
        std::cerr << "igmsctl: --config needs --to NAME (one of the lab's processes)\n";
        return std::nullopt;
      }
      const std::string to = vm["to"].as<std::string>();
      co.host = config.Get<std::string>("processes." + to + ".host", "127.0.0.1");
      co.port = static_cast<std::uint16_t>(config.Get<int>("processes." + to + ".port"));
    }
  } catch (const config::ConfigError& e) {
    std::cerr << "igmsctl: " << e.what() << "\n";
    return std::nullopt;
  }
  if (vm.count("port")) co.port = static_cast<std::uint16_t>(vm["port"].as<int>());
  if (vm.count("token")) co.token = vm["token"].as<std::string>();
  if (co.port == 0) {
    std::cerr << "igmsctl: say which server: --port P (and --host H), or --config FILE --to NAME\n";
    return std::nullopt;
  }
  return co;
}

// call and ping: one request, its response printed as JSON; the exit status.
int CallOnce(net::Client& client, const pb::MethodDescriptor* method, const pb::Message& request,
             std::chrono::milliseconds timeout) {
  int rc = kExitOk;
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  client.CallRaw(
      method->full_name(), request.SerializeAsString(), timeout,
      [&](const net::Status& status, std::string_view payload) {
        if (!status.ok()) {
          std::cerr << "igmsctl: " << method->full_name() << ": " << status.ToString() << "\n";
          // A server that cannot be reached is a wrong address as far as igmsctl can tell.
          rc = status.code == igms::TIMEOUT || status.code == igms::UNAVAILABLE ? kExitUsage
                                                                                : kExitFailure;
        } else {
          auto response = NewMessage(method->output_type());
          if (!response->ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
            std::cerr << "igmsctl: the response is not a " << method->output_type()->full_name()
                      << "\n";
            rc = kExitUsage;
          } else {
            std::cout << ToJson(*response) << std::endl;
          }
        }
        std::lock_guard lock(m);
        done = true;
        cv.notify_all();
      });
  std::unique_lock lock(m);
  cv.wait(lock, [&] { return done; });
  return rc;
}

// subscribe: each message as a line of JSON until --count, --duration, an error or Ctrl-C,
// then the rate and latency on stderr; the exit status.
int Subscribe(net::Client& client, const pb::MethodDescriptor* method, const pb::Message& request,
              std::chrono::milliseconds timeout, const po::variables_map& vm) {
  int rc = kExitOk;
  const long count = vm["count"].as<long>();
  const double duration = vm["duration"].as<double>();
  const bool quiet = vm.count("quiet") > 0;
  std::mutex m;
  std::condition_variable cv;
  std::vector<double> latencies_ms;
  long received = 0;
  bool failed = false;
  std::int64_t first_ns = 0, last_ns = 0;
  auto response = NewMessage(method->output_type());
  // The messages' send stamps are the server's clock: latencies across hosts need the
  // offset from this host's, estimated from pings before the stream starts.
  std::optional<net::ClockOffset> clock;
  if (vm["pings"].as<int>() > 0 && (count > 0 || duration > 0 || quiet)) {
    std::string error;
    clock = net::MeasureClockOffset(client, vm["pings"].as<int>(), timeout, &error);
    if (!clock)
      std::cerr << "igmsctl: no clock offset (latencies on raw stamps): " << error << "\n";
  }
  client.SubscribeRaw(
      method->full_name(), request.SerializeAsString(),
      [&](std::string_view payload, std::int64_t sent_ns) {
        const std::int64_t now = igms::UnixNs();
        std::lock_guard lock(m);
        if (count > 0 && received >= count) return;
        ++received;
        if (first_ns == 0) first_ns = now;
        last_ns = now;
        if (sent_ns > 0)
          latencies_ms.push_back(
              static_cast<double>(now - (clock ? clock->ToLocalNs(sent_ns) : sent_ns)) / 1e6);
        if (!quiet) {
          if (response->ParseFromArray(payload.data(), static_cast<int>(payload.size())))
            std::cout << ToJson(*response) << std::endl;
        }
        if (count > 0 && received >= count) cv.notify_all();
      },
      [&](const net::Status& status) {
        std::cerr << "igmsctl: " << method->full_name() << ": " << status.ToString() << "\n";
        std::lock_guard lock(m);
        failed = true;
        cv.notify_all();
      });
  std::signal(SIGINT, [](int) { g_interrupted = true; });
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_lock lock(m);
  while (!failed && !g_interrupted && !(count > 0 && received >= count) &&
         !(duration > 0 &&
           std::chrono::steady_clock::now() - t0 > std::chrono::duration<double>(duration))) {
    cv.wait_for(lock, 50ms);
  }
  if (failed) rc = 1;
  if (count > 0 || duration > 0 || quiet) {
    const double span_s = static_cast<double>(last_ns - first_ns) / 1e9;
    std::cerr << "igmsctl: " << received << " messages";
    if (received > 1 && span_s > 0)
      std::cerr << ", " << static_cast<double>(received - 1) / span_s << " per second";
    if (!latencies_ms.empty()) {
      std::cerr << ", latency p50 " << stats::Percentile(latencies_ms, 0.5) << " ms, p99 "
                << stats::Percentile(latencies_ms, 0.99) << " ms";
      if (clock) std::cerr << "; the server's clock " << clock->Describe() << " from this host's";
    }
    std::cerr << "\n";
  }
  if (count > 0 && received < count && !failed) rc = kExitUsage;
  return rc;
}

}  // namespace

int IgmsctlMain(int argc, char** argv) {
  const po::options_description opts = VisibleOptions();
  po::options_description hidden;
  hidden.add_options()("args", po::value<std::vector<std::string>>(), "");
  po::options_description all;
  all.add(opts).add(hidden);
  po::positional_options_description pos;
  pos.add("args", -1);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(argc, argv).options(all).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "igmsctl: " << e.what() << "\n";
    return kExitUsage;
  }
  if (vm.count("version")) {
    std::cout << version::Line("igmsctl") << "\n";
    return 0;
  }
  std::vector<std::string> args;
  if (vm.count("args")) args = vm["args"].as<std::vector<std::string>>();
  if (vm.count("help") || args.empty()) {
    std::cout << kUsage << "\n" << opts << "\n";
    return args.empty() && !vm.count("help") ? 2 : 0;
  }
  igms::log::Init("igmsctl", vm["log-level"].as<std::string>());
  const std::string command = args[0];

  if (command == "list") {
    for (const auto* m : AllMethods()) {
      std::cout << m->full_name() << (m->server_streaming() ? "  (stream)" : "") << "\n";
    }
    return kExitOk;
  }
  const pb::MethodDescriptor* method = CommandMethod(command, args);
  if (!method) return kExitUsage;
  if (command == "describe") {
    std::cout << method->full_name() << (method->server_streaming() ? " (stream)" : "") << "\n"
              << "  request:  " << Describe(method->input_type()) << "\n"
              << "  response: " << Describe(method->output_type()) << "\n";
    return kExitOk;
  }
  const auto request = MakeRequest(method, args, vm);
  if (!request) return kExitUsage;
  const auto co = ConnectionOptions(command, vm);
  if (!co) return kExitUsage;
  const auto timeout = std::chrono::milliseconds(vm["timeout"].as<int>());

  boost::asio::io_context io;
  auto work = boost::asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  net::Client client(io, *co);
  client.Start();
  int rc = kExitOk;
  if (command != "subscribe") {
    rc = CallOnce(client, method, *request, timeout);
    if (command == "ping" && rc == kExitOk && vm["pings"].as<int>() > 0) ReportClock(client, vm);
  } else {
    rc = Subscribe(client, method, *request, timeout, vm);
  }
  client.Stop();
  work.reset();
  io.stop();
  io_thread.join();
  return rc;
}

}  // namespace igms::tools
