#include "device_daemons/platform/platform_daemon.h"

namespace igms::devices {

config::Keys PlatformKeys(MollySimOptions* sim, double* poll_hz, DaemonConfig* daemon) {
  config::Keys keys = DaemonKeys(daemon);
  keys.Bind("poll_hz", poll_hz, "orientation polling rate, at most 80 Hz", "poll-hz");
  keys.Bind("backlash_deg", &sim->backlash_deg,
            "simulator: gear backlash on pitch and roll (thesis: 1.59)", "backlash-deg");
  return keys;
}

PlatformDaemon::PlatformDaemon(boost::asio::io_context& io, DaemonOptions options,
                               net::ServerOptions server, MollySimOptions sim, double poll_hz)
    : DaemonBase(io, "platform", "igms.devices.PlatformService", std::move(options),
                 std::move(server), poll_hz),
      sim_options_(sim),
      poll_hz_(poll_hz) {}

std::unique_ptr<SimulatedDevice> PlatformDaemon::MakeSimulator(std::string* error) {
  if (!sim_options_.Check(error)) return nullptr;
  return std::make_unique<MollySim>(sim_options_);
}

bool PlatformDaemon::StartDevice(const SerialLinkOptions& link, std::string* error) {
  PlatformDriverOptions options;
  options.link = link;
  options.poll_hz = poll_hz_;
  if (!options.Check(error)) return false;
  driver_ = std::make_unique<PlatformDriver>(io_, options,
                                             [this](const PlatformState& s) { hub().Publish(s); });
  driver_->Start();
  return true;
}

void PlatformDaemon::StopDevice() {
  if (driver_) driver_->Stop();
}

LinkStatus PlatformDaemon::DeviceStatus() const {
  LinkStatus status = driver_ ? driver_->status() : LinkStatus();
  status.set_controller(control_.Holder());
  return status;
}

bool PlatformDaemon::InjectInput(const SimInjectRequest&, SimulatedDevice&, SimInjectResponse*,
                                 std::string* error) {
  *error = "the platform simulator takes faults only; move it with PlatformService.SetOrientation";
  return false;
}

void PlatformDaemon::RegisterMethods(net::Server& server) {
  const auto unavailable = [](net::Reply<SetOrientationResponse>& reply) {
    reply(net::Status::Error(igms::UNAVAILABLE, "the platform is being replayed, not driven"));
  };
  server.HandleAsyncFrom<SetOrientationRequest, SetOrientationResponse>(
      "igms.devices.PlatformService.SetOrientation",
      [this, unavailable](const net::Caller& caller, const SetOrientationRequest& req,
                          net::Reply<SetOrientationResponse> reply) {
        if (!driver_) return unavailable(reply);
        if (req.steps_per_move() > molly::kMaxStepsPerMove) {
          return reply(net::Status::Error(igms::BAD_REQUEST, "steps_per_move must be <= 16383"));
        }
        const int32_t yaw_max = SignedFieldMax(molly::kYawBits);
        const int32_t pr_max = SignedFieldMax(molly::kPitchRollBits);
        if (std::abs(req.yaw_ticks()) > yaw_max || std::abs(req.pitch_ticks()) > pr_max ||
            std::abs(req.roll_ticks()) > pr_max) {
          return reply(net::Status::Error(
              igms::BAD_REQUEST,
              "ticks out of the protocol's range (yaw +-1048575, pitch and roll +-8191)"));
        }
        if (auto claim = control_.Claim(caller, req.take_control()); !claim.ok()) {
          return reply(claim);
        }
        driver_->SetOrientation(
            {req.yaw_ticks(), req.pitch_ticks(), req.roll_ticks()}, req.steps_per_move(),
            [reply](bool ok, const std::string& message) {
              reply(ok ? net::Status::Ok() : net::Status::Error(igms::UNAVAILABLE, message));
            });
      });
  server.HandleAsyncFrom<ResetZeroRequest, ResetZeroResponse>(
      "igms.devices.PlatformService.ResetZero",
      [this](const net::Caller& caller, const ResetZeroRequest& req,
             net::Reply<ResetZeroResponse> reply) {
        if (!driver_)
          return reply(
              net::Status::Error(igms::UNAVAILABLE, "the platform is being replayed, not driven"));
        if (auto claim = control_.Claim(caller, req.take_control()); !claim.ok()) {
          return reply(claim);
        }
        driver_->ResetZero([reply](bool ok, const std::string& message) {
          reply(ok ? net::Status::Ok() : net::Status::Error(igms::UNAVAILABLE, message));
        });
      });
}

}  // namespace igms::devices
