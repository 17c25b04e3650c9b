#include "control/app/control_config.h"

namespace igms::control {

config::Keys ControlKeys(ControlConfig* c) {
  config::Keys keys;
  SessionOptions& s = c->session;
  keys.Bind("all_axes", &s.all_axes, "slave pan, tilt and roll to the viewer (default: pan only)");
  keys.Bind("steps_per_move", &c->steps_per_move, "the platform's speed; 0 keeps its own");
  keys.Bind("settle_readings", &s.settle_readings,
            "freeze: readings in a row that must say the platform has stopped");
  keys.Bind("settle_timeout_ms", &c->settle_timeout_ms,
            "freeze: grab anyway after this long, saying so");
  keys.Bind("pointer_start_depth", &s.pointer_start_depth,
            "the pointer starts this far along the left camera's optical axis (world units)");
  keys.Bind("pointer_speed", &s.pointer_speed,
            "the pointer's speed at full stick deflection (world units a second)");
  keys.Bind("stick_dead_band", &s.stick_dead_band, "stick deflections below this read as zero");
  keys.Bind("world_units_per_inch", &s.world_units_per_inch,
            "the calibration's units per inch (the ranger measures inches)");
  keys.Bind("call_timeout_ms", &c->call_timeout_ms, "time-out of a call to a peer");
  keys.Bind("grab_timeout_ms", &c->grab_timeout_ms, "time-out of VideoService.Grab");
  keys.Bind("locate_timeout_ms", &c->locate_timeout_ms,
            "time-out of ObjectService.Locate (longer than the object server's frame fetch)");
  keys.Bind("stereo", &c->stereo,
            "the window's stereo output: side-by-side, anaglyph, quad-buffer, left, right or mono");
  keys.BindPath("export_dir", &c->export_dir,
                "rewrite every export format into this folder as the models change "
                "(docs/exports.md)",
                "", config::KeyType::kOutputPath);
  for (Peer peer : kAllPeers) {
    const std::string name(PeerName(peer));
    std::string help = "the process entry of the ";
    help.append(name).append(" peer (default: ").append(name).append(")");
    keys.Bind(name, &c->peer_names[static_cast<int>(peer)], help);
  }
  return keys;
}

Result<ControlAppOptions> MakeControlAppOptions(const config::ProcessOptions& process,
                                                const ControlConfig& c) {
  ControlAppOptions options;
  options.session = c.session;
  if (c.settle_timeout_ms <= 0 || c.call_timeout_ms <= 0 || c.grab_timeout_ms <= 0 ||
      c.locate_timeout_ms <= 0 || c.steps_per_move < 0) {
    return ErrorMessage{process.Key("") +
                        ": timeouts must be positive and steps_per_move not negative"};
  }
  options.session.settle_timeout_ns = int64_t{c.settle_timeout_ms} * 1'000'000;
  options.session.steps_per_move = static_cast<uint32_t>(c.steps_per_move);
  options.call_timeout = std::chrono::milliseconds(c.call_timeout_ms);
  options.grab_timeout = std::chrono::milliseconds(c.grab_timeout_ms);
  options.locate_timeout = std::chrono::milliseconds(c.locate_timeout_ms);
  options.token = process.lab.token;
  options.client_name = process.name;
  for (Peer peer : kAllPeers) {
    std::string name = c.peer_names[static_cast<int>(peer)];
    if (name.empty()) name = std::string(PeerName(peer));
    if (!process.config.Has("processes." + name)) continue;
    try {
      options.peers[peer] = PeerAddress{name, process.HostOf(name), process.PortOf(name)};
    } catch (const config::ConfigError& e) {
      return ErrorMessage{e.what()};
    }
  }
  return options;
}

}  // namespace igms::control
