// The platform's one controlling client (thesis 2.4: one operator moves the platform). The
// first connection to command the platform holds control until that connection closes; a
// command from another connection is refused, naming the holder, unless it asks to take
// control, and the one it was taken from is then refused with the name of the taker.
// No I/O: the daemon asks Claim() before each command.
#pragma once

#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/net/server.h"

namespace igms::devices {

class PlatformControl {
 public:
  // Ok when `caller` holds control after the call (it held it, it was free, or `take`);
  // otherwise PERMISSION_DENIED with a message for a person: who holds it and how to take it.
  net::Status Claim(const net::Caller& caller, bool take);
  // The holder for a person ("control at 127.0.0.1:40312"); empty when none.
  std::string Holder() const;

 private:
  struct Displaced {
    net::Caller client;
    std::string by;  // who took control from it
    std::string when;
  };
  // With mutex_ held: forgets a holder or displaced client whose connection has closed.
  void ForgetClosedLocked() const;

  mutable std::mutex mutex_;
  mutable std::optional<net::Caller> holder_;
  mutable std::vector<Displaced> displaced_;
};

}  // namespace igms::devices
