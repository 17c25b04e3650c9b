// Which peers may call which methods, by the name (CN) on their certificate
// (docs/security.md). Only with TLS: without it a peer has no name to judge.
//
// A rule is a method's full name ("igms.devices.PlatformService.SetOrientation"), its
// service's methods ("igms.devices.PlatformService.*"; the package may be left out:
// "PlatformService.*"), or "*". A method's own rule beats its service's, which beats "*";
// between two of a kind the later decides (the lab file's lab.permissions come after the
// built-in table). A rule's names
// may include "*": any certificate of the lab's authority.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace igms::net {

class Authorisation {
 public:
  // The built-in table: only the control client moves the platform or injects simulator
  // input; every certificate of the lab may call the rest (read, subscribe, grab, locate).
  static Authorisation Default();

  // Adds a rule, or replaces the one with the same pattern.
  void Set(const std::string& pattern, std::vector<std::string> names);
  bool Allowed(const std::string& method, const std::string& peer) const;
  // The names the deciding rule allows, for the refusal's message ("control").
  std::string WhoMay(const std::string& method) const;

 private:
  const std::pair<std::string, std::vector<std::string>>* Rule(const std::string& method) const;
  std::vector<std::pair<std::string, std::vector<std::string>>> rules_;
};

}  // namespace igms::net
