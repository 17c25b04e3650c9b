// DaemonBase: the process side every device daemon shares, over its device's driver.
//
// Depending on DaemonOptions it starts the device's simulator on a pseudo-terminal and the
// driver on it (--simulate), the driver on a real port (--serial), or a Replayer of a
// recording (--replay). Readings go through a ReadingHub to subscribers and the recording.
// It serves, under the device's service name S ("igms.devices.JoystickService"):
//   S.Live(SubscribeRequest) -> stream of the device's state, at the requested rate
//   S.Status(GetStatusRequest) -> LinkStatus
//   igms.devices.SimService.Inject(SimInjectRequest) -> faults and operator input
//     (simulated devices only; otherwise UNAVAILABLE)
// A derived daemon adds its own methods in RegisterMethods and its device input in
// InjectInput.
#pragma once

#include <boost/asio/io_context.hpp>
#include <memory>
#include <string>

#include "common/net/server.h"
#include "device_daemons/serial/daemon_options.h"
#include "device_daemons/serial/pty_host.h"
#include "device_daemons/serial/reading_hub.h"
#include "device_daemons/serial/recording.h"

namespace igms::devices {

template <class Msg>
class DaemonBase {
 public:
  DaemonBase(boost::asio::io_context& io, std::string device, std::string service,
             DaemonOptions options, net::ServerOptions server_options, double max_rate_hz)
      : io_(io),
        device_(std::move(device)),
        service_(std::move(service)),
        options_(std::move(options)),
        server_(io, std::move(server_options)),
        max_rate_hz_(max_rate_hz) {}
  virtual ~DaemonBase() = default;

  // Starts the source and the server. False with a message on failure.
  bool Start(std::string* error) {
    if (!options_.record_file.empty()) {
      auto writer = std::make_unique<RecordingWriter>();
      if (!writer->Open(options_.record_file, device_, error)) return false;
      hub_.Record(std::move(writer));
    }
    if (options_.source == SourceKind::kReplay) {
      auto recording = LoadRecording(options_.replay_file);
      if (!recording.ok()) return Fail(error, recording.error());
      if (recording->header.device() != device_) {
        *error = options_.replay_file + " records a " + recording->header.device() + ", not a " +
                 device_;
        return false;
      }
      replayer_ =
          std::make_unique<Replayer>(std::move(*recording), options_.replay_speed, options_.loop);
    } else {
      if (options_.source == SourceKind::kSimulate) {
        auto sim = MakeSimulator(error);
        if (!sim) return false;
        sim_ = std::make_unique<PtyHost>(std::move(sim),
                                         PtyHostOptions{options_.link.port, options_.link.baud});
        if (!sim_->Start(error)) return false;
      }
      // --sim-only: other software reads the simulator's link; the driver stays closed.
      if (!options_.sim_only && !StartDevice(options_.link, error)) return false;
    }
    RegisterCommon();
    RegisterMethods(server_);
    try {
      server_.Start();
    } catch (const std::exception& e) {
      *error = e.what();
      return false;
    }
    if (replayer_) {
      replayer_->Start([this](const Reading& r) {
        if (const Msg* m = UnwrapReading(r, static_cast<const Msg*>(nullptr))) hub_.Publish(*m);
      });
    }
    return true;
  }

  void Stop() {
    if (replayer_) replayer_->Stop();
    if (!options_.sim_only) StopDevice();
    server_.Stop();
    if (sim_) sim_->Stop();
  }

  uint16_t port() const { return server_.port(); }
  ReadingHub<Msg>& hub() { return hub_; }
  PtyHost* simulator() { return sim_.get(); }

 protected:
  virtual std::unique_ptr<SimulatedDevice> MakeSimulator(std::string* error) = 0;
  virtual bool StartDevice(const SerialLinkOptions& link, std::string* error) = 0;
  virtual void StopDevice() = 0;
  virtual LinkStatus DeviceStatus() const = 0;
  // Operator input for the simulator (runs under the simulator's lock); `response` says
  // what the device made of it, where it has something to say. False with a message when
  // the request holds no input this device takes.
  virtual bool InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                           SimInjectResponse* response, std::string* error) = 0;
  virtual void RegisterMethods(net::Server&) {}

  boost::asio::io_context& io_;
  std::string device_;
  std::string service_;
  DaemonOptions options_;

 private:
  void RegisterCommon() {
    server_.HandleStream<SubscribeRequest, Msg>(
        service_ + ".Live",
        [this](const SubscribeRequest& req, std::shared_ptr<net::Publisher<Msg>> pub) {
          if (!(req.rate_hz() >= 0))
            return net::Status::Error(igms::BAD_REQUEST, "rate_hz must be >= 0");
          const double rate =
              req.rate_hz() == 0 || req.rate_hz() >= max_rate_hz_ ? 0 : req.rate_hz();
          hub_.Subscribe(std::move(pub), rate);
          return net::Status::Ok();
        },
        /*latest_only=*/true);
    server_.Handle<GetStatusRequest, LinkStatus>(
        service_ + ".Status", [this](const GetStatusRequest&, LinkStatus& out) {
          if (replayer_) {
            out.set_state(REPLAYING);
            out.set_port(options_.replay_file);
            out.set_readings(hub_.published());
            out.set_message(replayer_->finished() ? "replay finished" : "replaying");
          } else if (options_.sim_only) {
            out.set_port(options_.link.port);
            out.set_message("the simulator alone on " + options_.link.port +
                            ": no driver reads it here");
          } else {
            out = DeviceStatus();
          }
          return net::Status::Ok();
        });
    server_.Handle<SimInjectRequest, SimInjectResponse>(
        "igms.devices.SimService.Inject",
        [this](const SimInjectRequest& req, SimInjectResponse& response) {
          if (!sim_) {
            return net::Status::Error(
                igms::UNAVAILABLE, "the " + device_ + " is not simulated (start with --simulate)");
          }
          if (req.has_fault()) {
            const SimFault& f = req.fault();
            if (f.garbage_bytes() > 4096 || f.stall_ms() > 60000 || f.vanish_ms() > 60000) {
              return net::Status::Error(
                  igms::BAD_REQUEST,
                  "fault too large (garbage <= 4096 bytes, stall and vanish <= 60 s)");
            }
            if (f.garbage_bytes()) sim_->InjectGarbage(f.garbage_bytes());
            if (f.stall_ms()) sim_->Stall(std::chrono::milliseconds(f.stall_ms()));
            if (f.vanish_ms()) sim_->Vanish(std::chrono::milliseconds(f.vanish_ms()));
            if (f.truncate_next()) sim_->TruncateNext();
            return net::Status::Ok();
          }
          std::string error;
          bool ok = false;
          sim_->WithDevice(
              [&](SimulatedDevice& d) { ok = InjectInput(req, d, &response, &error); });
          return ok ? net::Status::Ok() : net::Status::Error(igms::BAD_REQUEST, error);
        });
  }

  net::Server server_;
  double max_rate_hz_;
  ReadingHub<Msg> hub_;
  std::unique_ptr<PtyHost> sim_;
  std::unique_ptr<Replayer> replayer_;
};

// Runs a daemon until SIGINT or SIGTERM: the thin main of every igms-<device>d.
int RunDaemonProcess(boost::asio::io_context& io, const std::function<bool(std::string*)>& start,
                     const std::function<void()>& stop);

}  // namespace igms::devices
