#include "common/net/authorisation.h"

#include <algorithm>

namespace igms::net {

namespace {

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// How specifically `pattern` names `method`: -1 when it does not.
int Score(const std::string& pattern, const std::string& method) {
  if (pattern == "*") return 0;
  if (EndsWith(pattern, ".*")) {
    const std::string service = pattern.substr(0, pattern.size() - 1);  // "X.Service."
    const bool match =
        method.rfind(service, 0) == 0 || method.find("." + service) != std::string::npos;
    return match ? 1 + static_cast<int>(service.size()) : -1;
  }
  const bool match = method == pattern || EndsWith(method, "." + pattern);
  return match ? 1000 : -1;  // any exact rule beats any service rule
}

}  // namespace

Authorisation Authorisation::Default() {
  Authorisation a;
  a.Set("*", {"*"});
  a.Set("igms.devices.PlatformService.SetOrientation", {"control"});
  a.Set("igms.devices.PlatformService.ResetZero", {"control"});
  a.Set("igms.devices.SimService.*", {"control"});
  return a;
}

void Authorisation::Set(const std::string& pattern, std::vector<std::string> names) {
  for (auto& rule : rules_) {
    if (rule.first == pattern) {
      rule.second = std::move(names);
      return;
    }
  }
  rules_.emplace_back(pattern, std::move(names));
}

const std::pair<std::string, std::vector<std::string>>* Authorisation::Rule(
    const std::string& method) const {
  const std::pair<std::string, std::vector<std::string>>* best = nullptr;
  int best_score = -1;
  for (const auto& rule : rules_) {
    const int s = Score(rule.first, method);
    if (s >= best_score) {  // a tie goes to the later rule: the lab file's over the built-in
      best_score = s;
      best = &rule;
    }
  }
  return best;
}

bool Authorisation::Allowed(const std::string& method, const std::string& peer) const {
  const auto* rule = Rule(method);
  if (!rule) return false;  // no rule at all: nothing is allowed
  const auto& names = rule->second;
  return std::find(names.begin(), names.end(), "*") != names.end() ||
         (!peer.empty() && std::find(names.begin(), names.end(), peer) != names.end());
}

std::string Authorisation::WhoMay(const std::string& method) const {
  const auto* rule = Rule(method);
  if (!rule || rule->second.empty()) return "no one";
  std::string out;
  for (const auto& n : rule->second) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace igms::net
