#include "control/script/script_player.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cmath>
#include <functional>
#include <thread>
#include <utility>

#include "common/net/client.h"
#include "control/session/commands.h"

namespace igms::control {
namespace {

using std::chrono::milliseconds;
using Predicate = std::function<bool(const SessionView&)>;

// What the session shows once a command has acted, judged against the view before it.
Predicate EffectOf(CommandKind kind, const SessionView& before) {
  switch (kind) {
    case CommandKind::kFreeze:
      return [](const SessionView& v) { return v.mode == Mode::kModelBuilding; };
    case CommandKind::kUnfreeze:
      return [](const SessionView& v) { return v.mode == Mode::kVerification; };
    case CommandKind::kRange:
      return [n = before.ranges_taken](const SessionView& v) { return v.ranges_taken > n; };
    case CommandKind::kMark:
      return [n = before.marks.size()](const SessionView& v) { return v.marks.size() > n; };
    case CommandKind::kUnmark:
      return [n = before.marks.size()](const SessionView& v) { return v.marks.size() < n; };
    case CommandKind::kRemovePoints:
      return [](const SessionView& v) { return v.marks.empty(); };
    case CommandKind::kIdentifyBox:
    case CommandKind::kIdentifyCylinder:
      return [stored = before.models_stored, failed = before.locates_failed](const SessionView& v) {
        return v.models_stored > stored || v.locates_failed > failed;
      };
    case CommandKind::kWireframe:
      return [](const SessionView& v) { return v.wireframe; };
    case CommandKind::kSolid:
      return [](const SessionView& v) { return !v.wireframe; };
    case CommandKind::kToggleWireframe:
      return [w = before.wireframe](const SessionView& v) { return v.wireframe != w; };
    case CommandKind::kRemoveModel:
      return [n = before.present_models()](const SessionView& v) { return v.present_models() < n; };
    case CommandKind::kUndo:
      return [n = before.present_models(), m = before.marks.size()](const SessionView& v) {
        return v.present_models() != n || v.marks.size() != m;
      };
  }
  return [](const SessionView&) { return true; };
}

std::string Describe(const SessionView& v) {
  std::string down;
  for (Peer p : kAllPeers) {
    if (!v.peer_up[static_cast<int>(p)])
      down += (down.empty() ? "" : ",") + std::string(PeerName(p));
  }
  return fmt::format("mode {}, {} marks, {} models, {} stored, {} locates failed{}{}",
                     ModeName(v.mode), v.marks.size(), v.present_models(), v.models_stored,
                     v.locates_failed, down.empty() ? "" : ", down: " + down,
                     v.failure_detail.empty() ? "" : ", last failure: " + v.failure_detail);
}

}  // namespace

struct ScriptPlayer::Impl {
  ControlApp& app;
  ScriptPlayerOptions options;
  boost::asio::io_context io;
  std::optional<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>> work;
  std::thread thread;
  std::map<Peer, std::unique_ptr<net::Client>> sims;
  const Script* script = nullptr;
  const ScriptAction* action = nullptr;

  Impl(ControlApp& a, ScriptPlayerOptions o) : app(a), options(std::move(o)) {
    work.emplace(io.get_executor());
    for (const auto& [peer, address] : options.devices) {
      net::ClientOptions c;
      c.host = address.host;
      c.port = address.port;
      c.name = "script";
      c.token = options.token;
      c.max_backoff = milliseconds(500);
      sims[peer] = std::make_unique<net::Client>(io, c);
      sims[peer]->Start();
    }
    thread = std::thread([this] { io.run(); });
  }
  ~Impl() {
    for (auto& [peer, client] : sims) client->Stop();
    work.reset();
    thread.join();
  }

  ErrorMessage Fail(const std::string& what) const {
    return ErrorMessage{
        fmt::format("{}:{}: {}: {}", script->source, action->line, action->text, what)};
  }

  Result<devices::SimInjectResponse> Inject(Peer peer, const devices::SimInjectRequest& request) {
    auto it = sims.find(peer);
    if (it == sims.end()) {
      return Fail(fmt::format("the lab file has no {} daemon to inject into", PeerName(peer)));
    }
    auto r = it->second->CallSync<devices::SimInjectResponse>("igms.devices.SimService.Inject",
                                                              request, milliseconds(5000));
    if (!r.ok()) {
      return Fail(fmt::format("{}'s SimService.Inject: {}", PeerName(peer), r.status.ToString()));
    }
    return std::move(r.value);
  }

  // Waits until `pred` holds; the error names what was awaited and where the session is.
  Result<SessionView> Await(const Predicate& pred, const std::string& what) {
    SessionView last;
    const auto timeout = milliseconds(static_cast<int64_t>(action->timeout_s * 1000));
    const bool met = app.board().WaitFor(
        [&](const SessionView& v) { return pred(v) || v.exit_code.has_value(); }, timeout, &last);
    if (last.exit_code) return Fail("the session ended while waiting for " + what);
    if (!met) {
      return Fail(fmt::format("timed out after {:g} s waiting for {} ({})", action->timeout_s, what,
                              Describe(last)));
    }
    return last;
  }

  Result<bool> Buttons(bool left, bool right) {
    const auto command = CommandFromViewerButtons(left, right);
    const SessionView before = app.board().Get();
    devices::SimInjectRequest press;
    press.mutable_viewer_buttons()->set_button_left(left);
    press.mutable_viewer_buttons()->set_button_right(right);
    if (auto r = Inject(Peer::kViewer, press); !r.ok()) return ErrorMessage{r.error()};
    if (command) {
      auto seen = Await(EffectOf(*command, before), std::string(CommandName(*command)));
      if (!seen.ok()) return ErrorMessage{seen.error()};
      devices::SimInjectRequest release;
      release.mutable_viewer_buttons();
      if (auto r = Inject(Peer::kViewer, release); !r.ok()) return ErrorMessage{r.error()};
    }
    return true;
  }

  Result<bool> Joystick(double x, double y, double twist, uint32_t buttons, bool trigger) {
    devices::SimInjectRequest request;
    auto* j = request.mutable_joystick();
    j->set_x(x);
    j->set_y(y);
    j->set_twist(twist);
    j->set_buttons(buttons);
    j->set_trigger(trigger);
    if (auto r = Inject(Peer::kJoystick, request); !r.ok()) return ErrorMessage{r.error()};
    return true;
  }

  // A press of the trigger or a button, until the session shows its command's effect.
  Result<bool> Press(uint32_t buttons, bool trigger, std::optional<CommandKind> command) {
    const SessionView before = app.board().Get();
    if (auto r = Joystick(0, 0, 0, buttons, trigger); !r.ok()) return r;
    if (command) {
      auto seen = Await(EffectOf(*command, before), std::string(CommandName(*command)));
      if (!seen.ok()) return ErrorMessage{seen.error()};
    }
    return Joystick(0, 0, 0, 0, false);
  }

  Result<bool> Look(const ScriptAction& a) {
    devices::SimInjectRequest request;
    auto* viewer = request.mutable_viewer();
    viewer->set_yaw_deg(a.yaw);
    viewer->set_pitch_deg(a.pitch);
    viewer->set_roll_deg(a.roll);
    if (auto r = Inject(Peer::kViewer, request); !r.ok()) return ErrorMessage{r.error()};
    auto seen = Await(
        [&](const SessionView& v) {
          return v.viewer && std::abs(v.viewer->yaw_deg - a.yaw) < 0.05 &&
                 std::abs(v.viewer->pitch_deg - a.pitch) < 0.05 &&
                 std::abs(v.viewer->roll_deg - a.roll) < 0.05;
        },
        "the viewer's reading of the pose");
    if (!seen.ok()) return ErrorMessage{seen.error()};
    return true;
  }

  static constexpr int kSayAttempts = 3;

  Result<bool> Say(const ScriptAction& a) {
    // The daemon judges a word by the grammar it was last given: wait until it follows the
    // session's mode (a fourth mark switches it to the object-type grammar).
    auto ready = Await(
        [](const SessionView& v) {
          return !v.peer_up[static_cast<int>(Peer::kVoice)] ||
                 v.voice_grammar == OperatorStateOf(v.mode);
        },
        "the voice daemon's grammar to follow the mode");
    if (!ready.ok()) return ErrorMessage{ready.error()};
    const SessionView before = *ready;
    devices::SimInjectRequest request;
    request.set_spoken(a.phrase);
    // A recogniser may mishear; an operator not understood says it again, as often as
    // kSayAttempts. The simulated Dragon hears every word the first time.
    devices::SimHeard heard;
    for (int attempt = 1;; ++attempt) {
      auto r = Inject(Peer::kVoice, request);
      if (!r.ok()) return ErrorMessage{r.error()};
      heard = r->heard();
      if (heard.accepted()) break;
      const std::string why = fmt::format("heard '{}' ({}) in state {}{}", heard.text(),
                                          devices::VoiceCommand_Name(heard.command()),
                                          devices::OperatorState_Name(heard.state()),
                                          heard.detail().empty() ? "" : ": " + heard.detail());
      if (attempt == kSayAttempts) {
        return Fail(fmt::format("the voice daemon did not accept it {} times: {}", attempt, why));
      }
      spdlog::warn("{}:{}: not understood ({}); saying it again", script->source, a.line, why);
    }
    const auto command = CommandFromVoice(heard.command());
    if (!command) return true;
    auto seen = Await(EffectOf(*command, before), std::string(CommandName(*command)));
    if (!seen.ok()) return ErrorMessage{seen.error()};
    return true;
  }

  // A closed loop on the stick: deflect towards the point in the left camera's frame at the
  // grab (right = y, up = twist, forward = x), in proportion to the error, until the
  // pointer rests within the tolerance.
  Result<bool> MoveTo(const ScriptAction& a) {
    auto ready = Await([](const SessionView& v) { return v.frozen && v.pointer; },
                       "a frozen view with a pointer (freeze first)");
    if (!ready.ok()) return ErrorMessage{ready.error()};
    const CameraFrame frame = ready->frozen->left_frame;
    const auto deadline =
        std::chrono::steady_clock::now() + milliseconds(static_cast<int64_t>(a.timeout_s * 1000));
    auto deflect = [&](double error) {
      if (std::abs(error) < a.tolerance / 4) return 0.0;
      const double d = std::clamp(error / options.full_deflection_at, -1.0, 1.0);
      return std::abs(d) < options.min_deflection ? std::copysign(options.min_deflection, d) : d;
    };
    bool still = false;  // the stick is centred
    while (true) {
      const SessionView v = app.board().Get();
      if (v.exit_code) return Fail("the session ended");
      if (!v.frozen || !v.pointer) return Fail("the view was unfrozen while moving the pointer");
      const Eigen::Vector3d e = a.point - *v.pointer;
      if (e.norm() < a.tolerance) {
        if (still) return true;
        if (auto r = Joystick(0, 0, 0, 0, false); !r.ok()) return r;
        still = true;
        // Readings with the stick centred: the pointer has stopped where it is.
        const uint64_t version = v.version;
        app.board().WaitFor([&](const SessionView& now) { return now.version > version + 2; },
                            milliseconds(500));
        continue;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        // The stick released on the way out; the failure that follows is what to report.
        static_cast<void>(Joystick(0, 0, 0, 0, false));
        return Fail(fmt::format("the pointer did not reach the point within {:g} s ({:.3f} away)",
                                a.timeout_s, e.norm()));
      }
      still = false;
      if (auto r = Joystick(deflect(e.dot(frame.forward)), deflect(e.dot(frame.right)),
                            deflect(e.dot(frame.up())), 0, false);
          !r.ok()) {
        return r;
      }
      // The next readings moved the pointer (or the stick stalled: try again).
      const uint64_t version = v.version;
      app.board().WaitFor([&](const SessionView& now) { return now.version > version; },
                          milliseconds(200));
    }
  }

  Result<bool> WaitFor(const ScriptAction& a) {
    Predicate pred;
    std::string what;
    if (!a.mode.empty()) {
      pred = [m = a.mode](const SessionView& v) { return ModeName(v.mode) == m; };
      what = "mode " + a.mode;
    } else if (a.marks) {
      pred = [n = *a.marks](const SessionView& v) { return static_cast<int>(v.marks.size()) == n; };
      what = fmt::format("{} marks", *a.marks);
    } else if (a.models) {
      pred = [n = *a.models](const SessionView& v) {
        return static_cast<int>(v.present_models()) == n;
      };
      what = fmt::format("{} models", *a.models);
    } else {
      const bool up = !a.peer_up.empty();
      const std::string name = up ? a.peer_up : a.peer_down;
      pred = [up, name](const SessionView& v) {
        for (Peer p : kAllPeers) {
          if (PeerName(p) == name) return v.peer_up[static_cast<int>(p)] == up;
        }
        return false;
      };
      what = name + (up ? " up" : " down");
    }
    auto seen = Await(pred, what);
    if (!seen.ok()) return ErrorMessage{seen.error()};
    return true;
  }

  Result<bool> Fault(const ScriptAction& a) {
    Peer peer = Peer::kViewer;
    for (Peer p : kAllPeers) {
      if (PeerName(p) == a.device) peer = p;
    }
    devices::SimInjectRequest request;
    *request.mutable_fault() = a.fault;
    if (auto r = Inject(peer, request); !r.ok()) return ErrorMessage{r.error()};
    return true;
  }

  Result<bool> Run(const ScriptAction& a) {
    switch (a.kind) {
      case ActionKind::kLook:
        return Look(a);
      case ActionKind::kButton:
        return Buttons(a.left, a.right);
      case ActionKind::kRange:
        return Buttons(true, false);
      case ActionKind::kMoveTo:
        return MoveTo(a);
      case ActionKind::kTrigger:
        return Press(0, true, kJoystickTriggerCommand);
      case ActionKind::kJoystickButton:
        return Press(1u << (a.joystick_button - 1), false,
                     CommandFromJoystickButton(a.joystick_button));
      case ActionKind::kStick: {
        if (auto r = Joystick(a.x, a.y, a.twist, 0, false); !r.ok()) return r;
        if (a.seconds <= 0) return true;
        // Holding the stick for a while is the action itself.
        std::this_thread::sleep_for(std::chrono::duration<double>(a.seconds));
        return Joystick(0, 0, 0, 0, false);
      }
      case ActionKind::kSay:
        return Say(a);
      case ActionKind::kFault:
        return Fault(a);
      case ActionKind::kWaitFor:
        return WaitFor(a);
      case ActionKind::kScreenshot:
        if (options.screenshot) {
          if (auto r = options.screenshot(a.file); !r.ok()) return Fail("screenshot: " + r.error());
          spdlog::info("{}:{}: screenshot {}", script->source, a.line, a.file);
          return true;
        }
        spdlog::info("{}:{}: screenshot {} skipped: this client has no window", script->source,
                     a.line, a.file);
        return true;
    }
    return true;
  }
};

ScriptPlayer::ScriptPlayer(ControlApp& app, ScriptPlayerOptions options)
    : impl_(std::make_unique<Impl>(app, std::move(options))) {}

ScriptPlayer::~ScriptPlayer() = default;

Result<int> ScriptPlayer::Play(const Script& script) {
  impl_->script = &script;
  int played = 0;
  for (const ScriptAction& a : script.actions) {
    impl_->action = &a;
    spdlog::info("{}:{}: {}", script.source, a.line, a.text);
    auto r = impl_->Run(a);
    if (!r.ok()) return ErrorMessage{r.error()};
    played++;
  }
  return played;
}

}  // namespace igms::control
