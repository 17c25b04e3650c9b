#include "control/script/script.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "control/session/session.h"

namespace igms::control {
namespace {

struct BadScript {
  int line;
  std::string what;
};

int LineOf(const YAML::Node& node) { return node.Mark().line + 1; }

double Number(const YAML::Node& node, const std::string& what) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) throw BadScript{LineOf(node), what + " must be a finite number"};
    return v;
  } catch (const YAML::Exception&) {
    throw BadScript{LineOf(node), what + " must be a number"};
  }
}

std::string Text(const YAML::Node& node, const std::string& what) {
  if (!node.IsScalar()) throw BadScript{LineOf(node), what + " must be a word"};
  return node.as<std::string>();
}

// The keys of a map value, each known.
void OnlyKeys(const YAML::Node& node, const std::set<std::string>& known,
              const std::string& action) {
  if (!node.IsMap()) throw BadScript{LineOf(node), action + " takes a map"};
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    if (!known.count(key)) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      std::string what = action;
      what.append(": unknown key '").append(key).append("' (known: ").append(list).append(")");
      throw BadScript{LineOf(kv.first), std::move(what)};
    }
  }
}

Eigen::Vector3d Point(const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence() || node.size() != 3) {
    throw BadScript{LineOf(node), what + " must be [x, y, z]"};
  }
  return {Number(node[0], what), Number(node[1], what), Number(node[2], what)};
}

void ParseButton(const YAML::Node& v, ScriptAction* a) {
  const std::string b = Text(v, "button");
  static const std::map<std::string, std::pair<bool, bool>> kButtons = {
      {"none", {false, false}},   {"00", {false, false}},   {"freeze", {false, true}},
      {"01", {false, true}},      {"range", {true, false}}, {"10", {true, false}},
      {"unfreeze", {true, true}}, {"11", {true, true}}};
  auto it = kButtons.find(b);
  if (it == kButtons.end()) {
    throw BadScript{LineOf(v),
                    "button must be freeze, range, unfreeze, none or two digits (00, "
                    "01, 10, 11), not '" +
                        b + "'"};
  }
  a->left = it->second.first;
  a->right = it->second.second;
}

void ParseWaitFor(const YAML::Node& v, ScriptAction* a) {
  OnlyKeys(v, {"mode", "marks", "models", "peer_up", "peer_down", "timeout"}, "wait_for");
  int conditions = 0;
  if (v["mode"]) {
    a->mode = Text(v["mode"], "wait_for.mode");
    // As the session names it ("model building"); "model_building" reads the same.
    std::replace(a->mode.begin(), a->mode.end(), '_', ' ');
    bool known = false;
    for (Mode m : {Mode::kStarting, Mode::kVerification, Mode::kFreezing, Mode::kGrabbing,
                   Mode::kModelBuilding, Mode::kAwaitingType, Mode::kLocating, Mode::kStopped}) {
      known = known || ModeName(m) == a->mode;
    }
    if (!known)
      throw BadScript{LineOf(v["mode"]),
                      "wait_for.mode: no such mode '" + a->mode +
                          "' (known: starting, verification, freezing, grabbing, model "
                          "building, awaiting the object type, locating, stopped)"};
    conditions++;
  }
  auto count = [&](const char* key, std::optional<int>* out) {
    if (!v[key]) return;
    const double n = Number(v[key], std::string("wait_for.") + key);
    if (n < 0 || n != std::floor(n)) {
      throw BadScript{LineOf(v[key]), std::string("wait_for.") + key + " must be a count"};
    }
    *out = static_cast<int>(n);
    conditions++;
  };
  count("marks", &a->marks);
  count("models", &a->models);
  auto peer = [&](const char* key, std::string* out) {
    if (!v[key]) return;
    *out = Text(v[key], std::string("wait_for.") + key);
    bool known = false;
    for (Peer p : kAllPeers) known = known || PeerName(p) == *out;
    if (!known)
      throw BadScript{LineOf(v[key]), std::string("wait_for.") + key + ": no peer '" + *out + "'"};
    conditions++;
  };
  peer("peer_up", &a->peer_up);
  peer("peer_down", &a->peer_down);
  if (conditions != 1) {
    throw BadScript{LineOf(v), "wait_for takes one of mode, marks, models, peer_up, peer_down"};
  }
}

void ParseFault(const YAML::Node& v, ScriptAction* a) {
  OnlyKeys(v, {"device", "garbage_bytes", "stall_ms", "vanish_ms", "truncate_next"}, "fault");
  if (!v["device"]) throw BadScript{LineOf(v), "fault needs a device"};
  a->device = Text(v["device"], "fault.device");
  bool known = false;
  for (Peer p : kAllPeers) known = known || (IsDaemon(p) && PeerName(p) == a->device);
  if (!known) {
    throw BadScript{LineOf(v["device"]),
                    "fault.device must be a device daemon (viewer, joystick, "
                    "ranger, voice, platform), not '" +
                        a->device + "'"};
  }
  auto count = [&](const char* key) -> uint32_t {
    if (!v[key]) return 0;
    const double n = Number(v[key], std::string("fault.") + key);
    if (n < 0 || n > 1e6 || n != std::floor(n)) {
      throw BadScript{LineOf(v[key]), std::string("fault.") + key + " must be a count"};
    }
    return static_cast<uint32_t>(n);
  };
  a->fault.set_garbage_bytes(count("garbage_bytes"));
  a->fault.set_stall_ms(count("stall_ms"));
  a->fault.set_vanish_ms(count("vanish_ms"));
  if (v["truncate_next"]) {
    try {
      a->fault.set_truncate_next(v["truncate_next"].as<bool>());
    } catch (const YAML::Exception&) {
      throw BadScript{LineOf(v["truncate_next"]), "fault.truncate_next must be true or false"};
    }
  }
}

ScriptAction ParseAction(const YAML::Node& item) {
  ScriptAction a;
  a.line = LineOf(item);
  std::string name;
  YAML::Node v;
  if (item.IsScalar()) {
    name = item.as<std::string>();
  } else if (item.IsMap() && item.size() == 1) {
    name = item.begin()->first.as<std::string>();
    v = item.begin()->second;
  } else {
    throw BadScript{a.line, "an action is a word or a map with one key (the action)"};
  }
  std::ostringstream text;
  text << (item.IsScalar() ? name : YAML::Dump(item));
  a.text = text.str();
  for (char& c : a.text) c = c == '\n' ? ' ' : c;
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) throw BadScript{a.line, name + " " + what};
  };
  auto timeout = [&](const YAML::Node& node) {
    if (node.IsMap() && node["timeout"]) {
      a.timeout_s = Number(node["timeout"], name + ".timeout");
      if (a.timeout_s <= 0)
        throw BadScript{LineOf(node["timeout"]), name + ".timeout must be positive"};
    }
  };
  if (name == "look") {
    a.kind = ActionKind::kLook;
    OnlyKeys(v, {"yaw", "pitch", "roll", "timeout"}, "look");
    if (v["yaw"]) a.yaw = Number(v["yaw"], "look.yaw");
    if (v["pitch"]) a.pitch = Number(v["pitch"], "look.pitch");
    if (v["roll"]) a.roll = Number(v["roll"], "look.roll");
    need(std::abs(a.yaw) <= 180 && std::abs(a.pitch) <= 90 && std::abs(a.roll) <= 180,
         "angles must be within +/-180 (pitch +/-90) degrees");
    timeout(v);
  } else if (name == "button") {
    a.kind = ActionKind::kButton;
    need(v.IsDefined(), "needs a value");
    ParseButton(v, &a);
  } else if (name == "move_to") {
    a.kind = ActionKind::kMoveTo;
    need(v.IsDefined(), "needs a point");
    if (v.IsMap()) {
      OnlyKeys(v, {"point", "tolerance", "timeout"}, "move_to");
      need(v["point"].IsDefined(), "needs a point");
      a.point = Point(v["point"], "move_to.point");
      if (v["tolerance"]) a.tolerance = Number(v["tolerance"], "move_to.tolerance");
      need(a.tolerance > 0, "tolerance must be positive");
      timeout(v);
    } else {
      a.point = Point(v, "move_to");
    }
  } else if (name == "trigger") {
    a.kind = ActionKind::kTrigger;
    need(!v.IsDefined() || v.IsNull(), "takes no value");
  } else if (name == "range") {
    a.kind = ActionKind::kRange;
    need(!v.IsDefined() || v.IsNull(), "takes no value");
  } else if (name == "stick") {
    a.kind = ActionKind::kStick;
    OnlyKeys(v, {"x", "y", "twist", "seconds"}, "stick");
    if (v["x"]) a.x = Number(v["x"], "stick.x");
    if (v["y"]) a.y = Number(v["y"], "stick.y");
    if (v["twist"]) a.twist = Number(v["twist"], "stick.twist");
    if (v["seconds"]) a.seconds = Number(v["seconds"], "stick.seconds");
    need(std::abs(a.x) <= 1 && std::abs(a.y) <= 1 && std::abs(a.twist) <= 1,
         "deflections must be within [-1, 1]");
    need(a.seconds >= 0 && a.seconds <= 60, "seconds must be within 0-60");
  } else if (name == "joystick_button") {
    a.kind = ActionKind::kJoystickButton;
    need(v.IsDefined(), "needs a button number");
    const double b = Number(v, "joystick_button");
    need(b >= 1 && b <= 8 && b == std::floor(b), "must be a button 1-8");
    a.joystick_button = static_cast<int>(b);
  } else if (name == "say") {
    a.kind = ActionKind::kSay;
    need(v.IsDefined(), "needs a phrase");
    a.phrase = Text(v, "say");
    need(!a.phrase.empty(), "needs a phrase");
  } else if (name == "fault") {
    a.kind = ActionKind::kFault;
    need(v.IsDefined(), "needs a map");
    ParseFault(v, &a);
  } else if (name == "wait_for") {
    a.kind = ActionKind::kWaitFor;
    need(v.IsDefined(), "needs a condition");
    ParseWaitFor(v, &a);
    timeout(v);
  } else if (name == "screenshot") {
    a.kind = ActionKind::kScreenshot;
    need(v.IsDefined(), "needs a file name");
    a.file = Text(v, "screenshot");
  } else {
    throw BadScript{a.line, "unknown action '" + name +
                                "' (known: look, button, move_to, trigger, stick, "
                                "joystick_button, range, say, fault, wait_for, screenshot)"};
  }
  return a;
}

}  // namespace

std::string_view ActionName(ActionKind kind) {
  switch (kind) {
    case ActionKind::kLook:
      return "look";
    case ActionKind::kButton:
      return "button";
    case ActionKind::kMoveTo:
      return "move_to";
    case ActionKind::kTrigger:
      return "trigger";
    case ActionKind::kStick:
      return "stick";
    case ActionKind::kJoystickButton:
      return "joystick_button";
    case ActionKind::kRange:
      return "range";
    case ActionKind::kSay:
      return "say";
    case ActionKind::kFault:
      return "fault";
    case ActionKind::kWaitFor:
      return "wait_for";
    case ActionKind::kScreenshot:
      return "screenshot";
  }
  return "?";
}

Result<Script> ParseScript(const std::string& text, const std::string& source) {
  Script script;
  script.source = source;
  try {
    const YAML::Node root = YAML::Load(text);
    if (root.IsNull()) return script;  // an empty script does nothing
    if (!root.IsSequence()) {
      return ErrorMessage{source + ":" + std::to_string(LineOf(root)) +
                          ": a script is a list of actions (- look: ..., - trigger, ...)"};
    }
    for (const YAML::Node& item : root) script.actions.push_back(ParseAction(item));
  } catch (const BadScript& e) {
    return ErrorMessage{source + ":" + std::to_string(e.line) + ": " + e.what};
  } catch (const YAML::Exception& e) {
    return ErrorMessage{source + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg};
  }
  return script;
}

Result<Script> LoadScript(const std::string& path) {
  std::ifstream in(path);
  if (!in) return ErrorMessage{path + ": cannot read the script"};
  std::stringstream text;
  text << in.rdbuf();
  return ParseScript(text.str(), path);
}

}  // namespace igms::control
