#include "common/config/keys.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "common/config/lab_config.h"
#include "common/config/process_options.h"

namespace igms::config {

namespace {

constexpr const char* kLabPrefix = "lab.";

bool IsLabKey(const std::string& key) { return key.rfind(kLabPrefix, 0) == 0; }

std::string Where(const LabConfig& config, const YAML::Mark& mark) {
  if (mark.line < 0) return config.source();
  return config.source() + ":" + std::to_string(mark.line + 1);
}

std::string Where(const LabConfig& config, const YAML::Node& node) {
  return node.IsDefined() ? Where(config, node.Mark()) : config.source();
}

// Edits between two keys, a swap of neighbours counting as one ("vidoe" is one from "video").
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

// Walks a map of the file: every key that nothing declares is a problem. `prefix` is the
// key of `node` as declared ("" for processes.NAME, "lab." for lab); `shown` as printed.
void Walk(const LabConfig& config, const YAML::Node& node, const std::string& prefix,
          const std::string& shown, const std::vector<std::string>& declared, const Keys& keys,
          std::vector<KeyProblem>* problems) {
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    const std::string key = prefix + name;
    const YAML::Node value = kv.second;
    const bool has_children =
        std::any_of(declared.begin(), declared.end(),
                    [&](const std::string& d) { return d.rfind(key + ".", 0) == 0; });
    const KeySpec* spec = keys.Find(key);
    if (spec && (spec->type == KeyType::kMap || !has_children)) continue;
    if (has_children) {
      if (value.IsMap()) {
        Walk(config, value, key + ".", shown + name + ".", declared, keys, problems);
      } else if (!value.IsNull()) {
        problems->push_back({Where(config, kv.first), shown + name + " must be a map"});
      }
      continue;
    }
    std::string message = "unknown key ";
    message.append(shown).append(name);
    const std::string closest = ClosestKey(key, declared);
    if (!closest.empty()) {
      message += " (did you mean " + shown.substr(0, shown.size() - prefix.size()) + closest + "?)";
    }
    problems->push_back({Where(config, kv.first), message});
  }
}

std::string FullKey(const std::string& name, const std::string& key) {
  return IsLabKey(key) ? key : "processes." + name + "." + key;
}

}  // namespace

KeySpec& Keys::Declare(const std::string& key, KeyType type, const std::string& default_value,
                       const std::string& help) {
  auto it =
      std::find_if(specs_.begin(), specs_.end(), [&](const KeySpec& s) { return s.key == key; });
  if (it == specs_.end()) it = specs_.insert(specs_.end(), KeySpec{});
  it->key = key;
  it->type = type;
  it->default_value = default_value;
  it->help = help;
  return *it;
}

Keys& Keys::Add(const std::string& key, KeyType type, const std::string& default_value,
                const std::string& help) {
  Declare(key, type, default_value, help);
  return *this;
}

Keys& Keys::Choice(const std::string& key, std::vector<std::string> choices,
                   const std::string& default_value, const std::string& help) {
  Declare(key, KeyType::kString, default_value, help).choices = std::move(choices);
  return *this;
}

Keys& Keys::BindChoice(const std::string& key, std::string* field, std::vector<std::string> choices,
                       const std::string& help, const std::string& flag) {
  Bind(key, field, help, flag);
  Declare(key, KeyType::kString, *field, help).choices = std::move(choices);
  return *this;
}

Keys& Keys::BindPath(const std::string& key, std::string* field, const std::string& help,
                     const std::string& flag, KeyType type) {
  KeySpec& spec = Declare(key, type, *field, help);
  spec.flag = flag;
  readers_.push_back([spec = spec, field](const detail::KeySource& source) {
    if (source.flags && !spec.flag.empty() && source.flags->count(spec.flag)) {
      *field = (*source.flags)[spec.flag].as<std::string>();
      return;
    }
    const std::string full = FullKey(source.name, spec.key);
    if (source.config.Has(full)) {
      *field = source.config.ResolvePath(source.config.Get<std::string>(full));
    }
  });
  return *this;
}

Keys& Keys::Merge(const Keys& other) {
  for (const auto& spec : other.specs_)
    Declare(spec.key, spec.type, spec.default_value, spec.help) = spec;
  readers_.insert(readers_.end(), other.readers_.begin(), other.readers_.end());
  return *this;
}

Keys Keys::Declarations() const {
  Keys declared;
  declared.specs_ = specs_;
  return declared;
}

void Keys::Read(const ProcessOptions& process) const {
  const detail::KeySource source{process.config, process.name, &process.flags};
  for (const auto& read : readers_) read(source);
}

void Keys::Read(const LabConfig& config, const std::string& name) const {
  const detail::KeySource source{config, name};
  for (const auto& read : readers_) read(source);
}

const KeySpec* Keys::Find(const std::string& key) const {
  for (const auto& spec : specs_) {
    if (spec.key == key) return &spec;
  }
  return nullptr;
}

namespace {

const std::vector<std::string>& LogLevels() {
  static const std::vector<std::string> levels = {"trace", "debug",    "info", "warn",
                                                  "error", "critical", "off"};
  return levels;
}

Keys LabKeys(LabOptions* lab) {
  Keys k;
  k.Bind("lab.token", &lab->token,
         "a shared secret every client must present; empty: none (a closed lab network)");
  k.BindChoice("lab.tls", &lab->tls, {"off", "on"},
               "on: TLS 1.3 with mutual certificates on every connection (docs/security.md)");
  // Not a kPath: the folder need not exist (tls off, or systemd's credentials instead).
  k.BindPath("lab.certs", &lab->certs,
             "the folder of ca.crt, NAME.crt, NAME.key (empty: $CREDENTIALS_DIRECTORY, else certs "
             "beside the file)",
             "", KeyType::kString);
  k.Add("lab.permissions", KeyType::kMap, "",
        "method (or Service.*) to the certificate names that may call it, over the built-in "
        "table (docs/security.md)");
  k.BindPath("lab.calibration", &lab->calibration,
             "the cameras' calibration file (docs/calibration.md)");
  // Bound as written ("~/" is the home, not a folder beside the file), declared as the file
  // it names.
  k.Bind("lab.database", &lab->database, "the geometric database");
  k.Add("lab.database", KeyType::kOutputPath, "", "the geometric database");
  k.BindChoice("lab.log_level", &lab->log_level, LogLevels(),
               "every process's log level, under its own log_level and --log-level");
  return k;
}

Keys EntryKeys(ProcessEntry* entry) {
  Keys k;
  k.Bind("program", &entry->program, "the program that runs this process");
  k.Bind("host", &entry->host, "where the others find this process");
  k.Bind("port", &entry->port, "the port it listens on (0: any free port)");
  k.Bind("bind", &entry->bind,
         "the address it listens on; default: its host's (where the others reach it)");
  k.BindChoice("log_level", &entry->log_level, LogLevels(),
               "this process's log level, over lab.log_level", "log-level");
  return k;
}

}  // namespace

Keys CommonKeys(LabOptions* lab, ProcessEntry* entry) {
  Keys k = LabKeys(lab);
  k.Merge(EntryKeys(entry));
  return k;
}

const Keys& CommonKeys() {
  static const Keys keys = [] {
    LabOptions lab;
    ProcessEntry entry;
    return CommonKeys(&lab, &entry).Declarations();
  }();
  return keys;
}

LabOptions LabOptionsOf(const LabConfig& config) {
  LabOptions lab;
  LabKeys(&lab).Read(config);
  return lab;
}

std::string ClosestKey(const std::string& key, const std::vector<std::string>& declared) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(1, std::min<std::size_t>(3, key.size() / 3));
  for (const auto& candidate : declared) {
    const std::size_t d = EditDistance(key, candidate);
    if (d <= best_distance && (best.empty() || d < best_distance)) {
      best = candidate;
      best_distance = d;
    }
  }
  return best;
}

std::vector<KeyProblem> UnknownKeys(const LabConfig& config, const std::string& name,
                                    const Keys& keys) {
  std::vector<std::string> lab, own;
  for (const auto& spec : keys.specs()) (IsLabKey(spec.key) ? lab : own).push_back(spec.key);
  std::vector<KeyProblem> problems;
  const YAML::Node lab_node = config.Find("lab");
  if (lab_node.IsMap()) Walk(config, lab_node, kLabPrefix, kLabPrefix, lab, keys, &problems);
  const YAML::Node own_node = name.empty() ? YAML::Node() : config.Find("processes." + name);
  if (own_node.IsMap()) {
    Walk(config, own_node, "", "processes." + name + ".", own, keys, &problems);
  }
  return problems;
}

std::vector<KeyProblem> BadValues(const LabConfig& config, const std::string& name,
                                  const Keys& keys, bool paths) {
  std::vector<KeyProblem> problems;
  for (const auto& spec : keys.specs()) {
    const std::string key = FullKey(name, spec.key);
    const YAML::Node node = config.Find(key);
    if (!node.IsDefined() || node.IsNull()) continue;
    const auto bad = [&](const std::string& what) {
      std::string text = key;
      problems.push_back({Where(config, node), text.append(" ").append(what)});
    };
    const auto reads_as = [&](auto value) {
      try {
        node.as<decltype(value)>();
        return true;
      } catch (const YAML::Exception&) {
        return false;
      }
    };
    const std::string found = node.IsScalar() ? " (found '" + node.Scalar() + "')" : "";
    switch (spec.type) {
      case KeyType::kInt:
        if (!node.IsScalar() || !reads_as(0LL)) bad("must be an integer" + found);
        break;
      case KeyType::kNumber:
        if (!node.IsScalar() || !reads_as(0.0)) bad("must be a number" + found);
        break;
      case KeyType::kBool:
        if (!node.IsScalar() || !reads_as(false)) bad("must be true or false" + found);
        break;
      case KeyType::kList:
        if (!node.IsSequence()) bad("must be a list" + found);
        break;
      case KeyType::kMap:
        if (!node.IsMap()) bad("must be a map" + found);
        break;
      case KeyType::kString:
      case KeyType::kPath:
      case KeyType::kOutputPath:
        if (!node.IsScalar()) {
          bad("must be a single value, not a list or a map");
          break;
        }
        if (!spec.choices.empty() && std::find(spec.choices.begin(), spec.choices.end(),
                                               node.Scalar()) == spec.choices.end()) {
          std::string list;
          for (const auto& c : spec.choices) list.append(list.empty() ? "" : ", ").append(c);
          bad(list.insert(0, "must be one of ").append(found));
        }
        if (paths && spec.type == KeyType::kPath && !node.Scalar().empty()) {
          const std::string path = config.ResolvePath(node.Scalar());
          std::error_code ec;
          if (!std::filesystem::exists(path, ec)) bad("names " + path + ", which does not exist");
        }
        break;
    }
  }
  return problems;
}

namespace detail {

template <class T>
void ReadBound(const KeySource& source, const KeySpec& spec, T* field) {
  if (source.flags && !spec.flag.empty() && source.flags->count(spec.flag)) {
    const auto& flags = *source.flags;
    if constexpr (IsVector<T>::value) {
      // "1 2 3" or "1,2,3" on the command line.
      const auto& value = flags[spec.flag].value();
      if (const auto* text = boost::any_cast<std::string>(&value)) {
        std::string spaced = *text;
        std::replace(spaced.begin(), spaced.end(), ',', ' ');
        std::istringstream in(spaced);
        T values;
        for (typename T::value_type v; in >> v;) values.push_back(v);
        if (!in.eof()) {
          throw ConfigError("--" + spec.flag + ": expected numbers, found '" + *text + "'");
        }
        *field = std::move(values);
      } else {
        *field = flags[spec.flag].as<T>();
      }
      return;
    } else if constexpr (std::is_same_v<T, std::chrono::milliseconds>) {
      *field = std::chrono::milliseconds(flags[spec.flag].as<int>());
      return;
    } else if constexpr (IsOptional<T>::value) {
      *field = flags[spec.flag].as<typename T::value_type>();
      return;
    } else if constexpr (std::is_same_v<T, bool>) {
      // A switch: on when given; off leaves the file its say.
      if (flags[spec.flag].as<bool>()) {
        *field = true;
        return;
      }
    } else {
      *field = flags[spec.flag].as<T>();
      return;
    }
  }
  const std::string key = FullKey(source.name, spec.key);
  if constexpr (std::is_same_v<T, std::chrono::milliseconds>) {
    *field = std::chrono::milliseconds(source.config.Get<long long>(key, field->count()));
  } else if constexpr (IsOptional<T>::value) {
    if (source.config.Has(key)) *field = source.config.Get<typename T::value_type>(key);
  } else {
    *field = source.config.Get<T>(key, *field);
  }
}

template void ReadBound<bool>(const KeySource&, const KeySpec&, bool*);
template void ReadBound<int>(const KeySource&, const KeySpec&, int*);
template void ReadBound<unsigned>(const KeySource&, const KeySpec&, unsigned*);
template void ReadBound<unsigned long>(const KeySource&, const KeySpec&, unsigned long*);
template void ReadBound<double>(const KeySource&, const KeySpec&, double*);
template void ReadBound<float>(const KeySource&, const KeySpec&, float*);
template void ReadBound<std::string>(const KeySource&, const KeySpec&, std::string*);
template void ReadBound<std::chrono::milliseconds>(const KeySource&, const KeySpec&,
                                                   std::chrono::milliseconds*);
template void ReadBound<std::vector<double>>(const KeySource&, const KeySpec&,
                                             std::vector<double>*);
template void ReadBound<std::vector<int>>(const KeySource&, const KeySpec&, std::vector<int>*);
template void ReadBound<std::vector<bool>>(const KeySource&, const KeySpec&, std::vector<bool>*);
template void ReadBound<std::optional<int>>(const KeySource&, const KeySpec&, std::optional<int>*);
template void ReadBound<std::optional<double>>(const KeySource&, const KeySpec&,
                                               std::optional<double>*);

}  // namespace detail

}  // namespace igms::config
