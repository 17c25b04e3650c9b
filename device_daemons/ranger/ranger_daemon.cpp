#include "device_daemons/ranger/ranger_daemon.h"

namespace igms::devices {

RangerDaemon::RangerDaemon(boost::asio::io_context& io, DaemonOptions options, net::ServerOptions server,
                           RangerDaemonOptions ranger)
    : DaemonBase(io, "ranger", "igms.devices.RangerService", std::move(options), std::move(server), udm::kMaxRateHz),
      ranger_(std::move(ranger)) {}

RangerDaemon::~RangerDaemon() {
  if (platform_) platform_->Stop();
}

std::unique_ptr<SimulatedDevice> RangerDaemon::MakeSimulator(std::string*) {
  auto sim = std::make_unique<RangerSim>();
  if (ranger_.follow_platform_port != 0) {
    net::ClientOptions o;
    o.host = ranger_.platform_host;
    o.port = ranger_.follow_platform_port;
    o.name = "ranger-sim";
    o.token = ranger_.token;
    platform_ = std::make_unique<net::Client>(io_, o);
    platform_->Start();
    RangerSim* raw = sim.get();
    platform_->Subscribe<PlatformState>("igms.devices.PlatformService.Live", SubscribeRequest(),
                                        [this, raw](const PlatformState& p) {
                                          RangerPose pose;
                                          pose.yaw_deg = p.yaw_deg();
                                          pose.pitch_deg = p.pitch_deg();
                                          simulator()->WithDevice([&](SimulatedDevice&) { raw->SetPose(pose); });
                                        });
  }
  return sim;
}

bool RangerDaemon::StartDevice(const SerialLinkOptions& link, std::string* error) {
  RangerDriverOptions options;
  options.link = link;
  options.poll_hz = ranger_.poll_hz;
  if (!options.Check(error)) return false;
  driver_ = std::make_unique<RangerDriver>(io_, options, [this](const RangerState& s) { hub().Publish(s); });
  driver_->Start();
  return true;
}

void RangerDaemon::StopDevice() {
  if (platform_) platform_->Stop();
  if (driver_) driver_->Stop();
}

LinkStatus RangerDaemon::DeviceStatus() const { return driver_ ? driver_->status() : LinkStatus(); }

bool RangerDaemon::InjectInput(const SimInjectRequest& request, SimulatedDevice& sim, std::string* error) {
  if (!request.has_ranger()) {
    *error = "the ranger simulator takes a RangerState (or a fault)";
    return false;
  }
  const RangerState& r = request.ranger();
  auto& ranger = static_cast<RangerSim&>(sim);
  ranger.Override(r.valid() ? std::optional<double>(r.range_in()) : std::nullopt);
  return true;
}

void RangerDaemon::RegisterMethods(net::Server& server) {
  server.HandleAsync<RangeRequest, RangerState>(
      "igms.devices.RangerService.Range", [this](const RangeRequest&, net::Reply<RangerState> reply) {
        if (!driver_) return reply(net::Status::Error(igms::UNAVAILABLE, "the ranger is being replayed, not driven"));
        driver_->Range([reply](bool ok, const RangerState& state, const std::string& message) {
          reply(ok ? net::Status::Ok() : net::Status::Error(igms::UNAVAILABLE, message), state);
        });
      });
}

}  // namespace igms::devices
