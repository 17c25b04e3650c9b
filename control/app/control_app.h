// The control client's I/O side (Cooke, *Interactive Graphical Model Building using Virtual
// Reality* (1993), section 2.4 and figure 2-5): it connects the session's state machine
// (control/session) to every peer of the lab and to the geometric database.
//
//   - One network thread runs everything: the peers' replies and streams, the timers and the
//     session, so the session is only ever touched from there.
//   - Start: every configured peer is pinged and checked (a daemon's serial link, the video
//     and object servers' calibration hash against ours, the sound bank); the outcome is the
//     session's StartEvent. A peer that comes later (`--wait`) or comes back is checked again
//     and becomes a PeerUpEvent; a lost connection a PeerDownEvent.
//   - Effects become calls; each reply becomes the event the session waits for. A call to a
//     peer that is down is answered at once with UNAVAILABLE.
//   - Models go to the database as the session stores them; a continued database's models
//     are handed to the session before it starts.
//   - After every event a SessionView is published for the window and the script player.
// docs/control.md describes the contract.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "common/base/result.h"
#include "common/calibration/calibration_file.h"
#include "control/app/session_view.h"
#include "control/database/geometric_database.h"
#include "control/session/session.h"

namespace igms::control {

struct PeerAddress {
  std::string name;  // its entry under processes
  std::string host;
  uint16_t port = 0;
  std::string ToString() const { return host + ":" + std::to_string(port); }
};

struct ControlAppOptions {
  SessionOptions session;
  std::map<Peer, PeerAddress> peers;  // the configured ones; a missing one is reported missing
  std::string token;
  std::string client_name = "control";
  std::string calibration_hash;  // ours; peers that report another are refused
  std::chrono::milliseconds call_timeout{2000};
  std::chrono::milliseconds grab_timeout{5000};
  // Longer than the object server's frame fetch (2 s) plus a locate on a loaded machine.
  std::chrono::milliseconds locate_timeout{30000};
  std::chrono::milliseconds range_timeout{3000};
  std::chrono::milliseconds tick{20};
  std::chrono::milliseconds health_period{1000};
  // Called on the network thread with the models present after each change the database
  // committed (and once at start): the exports. It must return quickly.
  std::function<void(std::vector<StoredModel>)> models_changed;
  // Called on the network thread with every view as it is published, and the client's
  // CLOCK_MONOTONIC then: for benchmarks that time a reading to the change it causes (the
  // board keeps only the newest view). It must return quickly.
  std::function<void(const SessionView&, int64_t now_ns)> view_published;

  bool Check(std::string* error) const;
};

class ControlApp {
 public:
  // `database` may be null (a session that stores nothing: tests of the I/O alone).
  static Result<std::unique_ptr<ControlApp>> Make(ControlAppOptions options,
                                                  const calibration::StereoCalibration& calibration,
                                                  std::unique_ptr<GeometricDatabase> database);
  ~ControlApp();
  ControlApp(const ControlApp&) = delete;
  ControlApp& operator=(const ControlApp&) = delete;

  // Starts the network thread, the peers and the start-up checks; returns at once.
  void Start();
  // Blocks until the session ends (a required peer missing without --wait) or Stop(); the
  // exit code (0 after Stop).
  int Wait();
  // Ends the session from any thread (a signal, the window closing, the end of a script).
  void Stop(int exit_code = 0);

  // Commands from sources with no device of their own (the window's keys and mouse, a
  // script); thread-safe.
  void Post(const Command& command);
  void Post(const PointerDrive& drive);

  const ViewBoard& board() const;
  // The client's CLOCK_MONOTONIC, the clock of every event it hands the session.
  static int64_t NowNs();

  struct Impl;

 private:
  explicit ControlApp(std::shared_ptr<Impl> impl);
  std::shared_ptr<Impl> impl_;
};

}  // namespace igms::control
