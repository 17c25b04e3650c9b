// The control client: its options checked, the session fed from the network loop, the
// timers, and the interface control_app.h gives the program.
#include "control/app/control_app_impl.h"

namespace igms::control {

using app_detail::LevelOf;
using app_detail::Service;

void ControlApp::Impl::Handle(const Event& event) {
  if (exit_code) return;
  const Effects effects = session->Handle(event);
  for (const Effect& effect : effects) std::visit([&](const auto& e) { Execute(e); }, effect);
  // Ticks come 50 times a second and mostly change nothing the display shows.
  if (!effects.empty() || !std::holds_alternative<TickEvent>(event)) Publish();
}

void ControlApp::Impl::Publish() {
  view.version++;
  if (session->mode() != view.mode || view.version == 1) {
    spdlog::info("mode: {}", ModeName(session->mode()));
  }
  view.mode = session->mode();
  view.viewer = session->viewer();
  for (Peer p : kAllPeers) view.peer_up[static_cast<int>(p)] = session->peer_up(p);
  view.wireframe = session->wireframe();
  view.pointer = session->pointer();
  view.marks = session->marks();
  view.models = session->models();
  view.frozen = session->frozen();
  view.range = session->range();
  view.failure_detail = session->failure_detail();
  view.platform_target = session->platform_target();
  board.Publish(view);
  if (options.view_published) options.view_published(view, NowNs());
}

void ControlApp::Impl::Note(spdlog::level::level_enum level, std::string text) {
  spdlog::log(level, "{}", text);
  view.notices.push_back(NoticeLine{LevelOf(level), std::move(text), ++notices});
  while (view.notices.size() > SessionView::kKeptNotices) view.notices.pop_front();
}

void ControlApp::Impl::Finish(int code) {
  {
    std::lock_guard lock(exit_mutex);
    if (exit_code) return;
    exit_code = code;
  }
  view.exit_code = code;
  board.Publish(view);
  exited.notify_all();
}

void ControlApp::Impl::Tick() {
  if (shutting_down) return;
  Handle(TickEvent{NowNs()});
  tick_timer.expires_after(options.tick);
  tick_timer.async_wait([weak = weak_from_this()](const boost::system::error_code& ec) {
    if (auto self = weak.lock(); self && !ec) self->Tick();
  });
}

void ControlApp::Impl::Health() {
  if (shutting_down) return;
  for (auto& [peer, link] : links) {
    if (!link.client->connected()) continue;
    if (!link.up) {
      CheckAndReport(link);
      continue;
    }
    if (!IsDaemon(peer)) continue;
    link.client->Call<devices::LinkStatus>(
        Service(peer) + ".Status", devices::GetStatusRequest(), options.call_timeout,
        [this, peer = peer](const net::Result<devices::LinkStatus>& r) {
          if (!r.ok()) return;  // a lost connection is reported by the client
          Link* link = LinkOf(peer);
          if (r.value.state() == link->link_state) return;
          link->link_state = r.value.state();
          Handle(DeviceLinkEvent{peer, r.value.state(), r.value.message(), NowNs()});
        });
  }
  health_timer.expires_after(options.health_period);
  health_timer.async_wait([weak = weak_from_this()](const boost::system::error_code& ec) {
    if (auto self = weak.lock(); self && !ec) self->Health();
  });
}

void ControlApp::Impl::Shutdown() {
  shutting_down = true;
  tick_timer.cancel();
  health_timer.cancel();
  for (auto& [peer, link] : links) link.client->Stop();
  work.reset();
}

bool ControlAppOptions::Check(std::string* error) const {
  auto fail = [&](std::string why) {
    if (error) *error = std::move(why);
    return false;
  };
  if (!session.Check(error)) return false;
  for (const auto& [peer, address] : peers) {
    if (address.host.empty() || address.port == 0) {
      return fail("processes." + address.name + ": needs a host and a port for the " +
                  std::string(PeerName(peer)) + " peer");
    }
  }
  if (call_timeout.count() <= 0 || grab_timeout.count() <= 0 || locate_timeout.count() <= 0 ||
      range_timeout.count() <= 0) {
    return fail("call timeouts must be positive");
  }
  if (tick.count() <= 0 || health_period.count() <= 0) {
    return fail("the tick and the health period must be positive");
  }
  return true;
}

int64_t ControlApp::NowNs() { return MonotonicNs(); }

Result<std::unique_ptr<ControlApp>> ControlApp::Make(
    ControlAppOptions options, const calibration::StereoCalibration& calibration,
    std::unique_ptr<GeometricDatabase> database) {
  std::string error;
  if (!options.Check(&error)) return ErrorMessage{error};
  auto session = Session::Make(options.session, calibration, &error);
  if (!session) return ErrorMessage{error};
  auto impl = std::make_shared<Impl>();
  impl->options = std::move(options);
  impl->database = std::move(database);
  impl->session = std::move(session);
  return std::unique_ptr<ControlApp>(new ControlApp(std::move(impl)));
}

ControlApp::ControlApp(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}

ControlApp::~ControlApp() {
  Stop();
  if (impl_->thread.joinable()) {
    asio::post(impl_->io, [impl = impl_] { impl->Shutdown(); });
    // Closing every connection and ending the timers ends io.run(). Should anything still
    // hold it (a defect), the client must not hang on its way out: the loop is stopped after
    // a grace period, which leaves nothing unsaved (every model is committed before the
    // session hears of it). tests/control/app checks the grace is not needed.
    auto ended = impl_->loop_ended.get_future();
    if (ended.wait_for(std::chrono::seconds(3)) != std::future_status::ready) {
      spdlog::warn("control client: the network loop did not end by itself; stopping it");
      impl_->io.stop();
    }
    impl_->thread.join();
  }
}

void ControlApp::Start() {
  impl_->work.emplace(impl_->io.get_executor());
  impl_->Publish();
  asio::post(impl_->io, [impl = impl_] { impl->Connect(); });
  impl_->thread = std::thread([impl = impl_] {
    // An exception here is a defect; say what it was rather than leave a hung client.
    try {
      impl->io.run();
    } catch (const std::exception& e) {
      spdlog::critical("control client: {}", e.what());
      impl->Finish(1);
    }
    impl->loop_ended.set_value();
  });
}

int ControlApp::Wait() {
  std::unique_lock lock(impl_->exit_mutex);
  impl_->exited.wait(lock, [&] { return impl_->exit_code.has_value(); });
  return *impl_->exit_code;
}

void ControlApp::Stop(int exit_code) {
  asio::post(impl_->io, [impl = impl_, exit_code] { impl->Finish(exit_code); });
  if (!impl_->thread.joinable()) impl_->Finish(exit_code);
}

void ControlApp::Post(const Command& command) {
  asio::post(impl_->io, [impl = impl_, command] {
    if (impl->started) impl->Handle(CommandEvent{command, NowNs()});
  });
}

void ControlApp::Post(const PointerDrive& drive) {
  asio::post(impl_->io, [impl = impl_, drive] {
    if (impl->started) impl->Handle(PointerDriveEvent{drive, NowNs()});
  });
}

const ViewBoard& ControlApp::board() const { return impl_->board; }

}  // namespace igms::control
