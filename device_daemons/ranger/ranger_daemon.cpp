#include "device_daemons/ranger/ranger_daemon.h"

#include <spdlog/spdlog.h>

namespace igms::devices {

config::Keys RangerKeys(RangerDaemonOptions* options, DaemonConfig* daemon) {
  config::Keys keys = DaemonKeys(daemon);
  keys.Bind("poll_hz", &options->poll_hz,
            "also range continuously at this rate, at most 6 Hz (0: on request only)", "poll-hz");
  keys.BindPath("scene", &options->scene_file,
                "simulator: the site's scene file (default: the thesis testbed)", "scene");
  keys.BindPath("calibration", &options->calibration_file,
                "simulator: the ranger's mount and the platform model (default: lab.calibration)",
                "calibration");
  keys.Bind("platform", &options->platform,
            "simulator: the platform process whose pose turns the beam");
  return keys;
}

RangerDaemon::RangerDaemon(boost::asio::io_context& io, DaemonOptions options,
                           net::ServerOptions server, RangerDaemonOptions ranger)
    : DaemonBase(io, "ranger", "igms.devices.RangerService", std::move(options), std::move(server),
                 udm::kMaxRateHz),
      ranger_(std::move(ranger)) {}

RangerDaemon::~RangerDaemon() {
  if (platform_) platform_->Stop();
}

std::unique_ptr<SimulatedDevice> RangerDaemon::MakeSimulator(std::string* error) {
  RangerSimOptions sim_options;
  auto world = LoadRangerWorld(ranger_.scene_file, ranger_.calibration_file);
  if (!world.ok()) {
    *error = world.error();
    return nullptr;
  }
  sim_options.world = std::move(*world);
  if (!sim_options.world.mount.platform && ranger_.follow_platform_port != 0) {
    spdlog::warn("ranger simulator: the calibration has no platform model, so the beam stays put");
  }
  const RangerBeam beam = sim_options.world.mount.BeamAt({});
  spdlog::info(
      "ranger simulator: beam from ({:.2f}, {:.2f}, {:.2f}) along ({:.3f}, {:.3f}, {:.3f}) at the "
      "zero pose",
      beam.origin.x(), beam.origin.y(), beam.origin.z(), beam.axis.x(), beam.axis.y(),
      beam.axis.z());
  auto sim = std::make_unique<RangerSim>(std::move(sim_options));
  if (ranger_.follow_platform_port != 0) {
    net::ClientOptions o;
    o.host = ranger_.platform_host;
    o.port = ranger_.follow_platform_port;
    o.name = "ranger-sim";
    o.token = ranger_.token;
    o.reconnect = true;
    platform_ = std::make_unique<net::Client>(io_, o);
    platform_->Start();
    RangerSim* raw = sim.get();
    platform_->Subscribe<PlatformState>(
        "igms.devices.PlatformService.Live", SubscribeRequest(),
        [this, raw](const PlatformState& p) {
          simulator()->WithDevice([&](SimulatedDevice&) { raw->SetPlatform(p); });
        });
  }
  return sim;
}

bool RangerDaemon::StartDevice(const SerialLinkOptions& link, std::string* error) {
  RangerDriverOptions options;
  options.link = link;
  options.poll_hz = ranger_.poll_hz;
  if (!options.Check(error)) return false;
  driver_ = std::make_unique<RangerDriver>(io_, options,
                                           [this](const RangerState& s) { hub().Publish(s); });
  driver_->Start();
  return true;
}

void RangerDaemon::StopDevice() {
  if (platform_) platform_->Stop();
  if (driver_) driver_->Stop();
}

LinkStatus RangerDaemon::DeviceStatus() const { return driver_ ? driver_->status() : LinkStatus(); }

bool RangerDaemon::InjectInput(const SimInjectRequest& request, SimulatedDevice& sim,
                               SimInjectResponse*, std::string* error) {
  auto& ranger = static_cast<RangerSim&>(sim);
  if (request.has_platform()) {
    ranger.SetPlatform(request.platform());
    return true;
  }
  if (!request.has_ranger()) {
    *error = "the ranger simulator takes a RangerState, a PlatformState (or a fault)";
    return false;
  }
  const RangerState& r = request.ranger();
  if (r.valid() && r.range_in() == 0) {
    ranger.Release();
  } else {
    ranger.Override(r.valid() ? std::optional<double>(r.range_in()) : std::nullopt);
  }
  return true;
}

void RangerDaemon::RegisterMethods(net::Server& server) {
  server.HandleAsync<RangeRequest, RangerState>(
      "igms.devices.RangerService.Range",
      [this](const RangeRequest&, net::Reply<RangerState> reply) {
        if (!driver_)
          return reply(
              net::Status::Error(igms::UNAVAILABLE, "the ranger is being replayed, not driven"));
        driver_->Range([reply](bool ok, const RangerState& state, const std::string& message) {
          reply(ok ? net::Status::Ok() : net::Status::Error(igms::UNAVAILABLE, message), state);
        });
      });
}

}  // namespace igms::devices
