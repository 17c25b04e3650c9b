// igms certs: the lab's certificate authority (docs/security.md).
//
//   igms certs init  [--dir D] [--days 3650]           makes the authority (ca.key, ca.crt)
//   igms certs issue NAME [--dir D] [--host H]... [--days 365] [--config FILE]
//   igms certs lab   --config FILE [--dir D] [--renew]  the authority and every process's
//   igms certs show  [FILE | NAME] [--dir D]            what a certificate says
//
// The folder is --dir, else the lab file's lab.certs, else `certs` beside the lab file.
// With --config, issue checks NAME against the lab's processes (igmsctl is the diagnostic
// client's name and always allowed) and names the process's host in the certificate.
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "common/base/environment.h"
#include "common/certs/certs.h"
#include "common/config/exit_codes.h"
#include "common/config/lab_config.h"
#include "common/config/process_options.h"
#include "common/version/version.h"

namespace {

using igms::certs::Info;

constexpr const char* kDiagnosticName = "igmsctl";

std::string Date(std::int64_t t) {
  const auto tt = static_cast<std::time_t>(t);
  std::tm tm{};
  gmtime_r(&tt, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

int Usage(const std::string& why) {
  if (!why.empty()) std::cerr << "igms certs: " << why << "\n";
  std::cerr << "usage: igms certs init [--dir D] [--days N]\n"
               "       igms certs issue NAME [--dir D] [--host H]... [--days N] [--config FILE]\n"
               "       igms certs lab --config FILE [--dir D] [--renew]\n"
               "       igms certs show [FILE | NAME] [--dir D]\n";
  return why.empty() ? igms::kExitOk : igms::kExitUsage;
}

void Show(const std::string& path) {
  const Info info = igms::certs::Describe(igms::certs::ReadFile(path));
  const auto now = static_cast<std::int64_t>(std::time(nullptr));
  std::cout << path << "\n  name:    " << info.subject
            << (info.is_authority ? " (an authority)" : "") << "\n  issuer:  " << info.issuer
            << "\n  valid:   " << Date(info.not_before_unix) << " to " << Date(info.not_after_unix);
  if (info.not_after_unix <= now) {
    std::cout << " (EXPIRED)";
  } else {
    std::cout << " (" << (info.not_after_unix - now) / 86400 << " days left)";
  }
  std::cout << "\n";
  if (!info.hosts.empty()) {
    std::cout << "  hosts:  ";
    for (const auto& h : info.hosts) std::cout << " " << h;
    std::cout << "\n";
  }
}

// The hosts a process is reached at: its host in the lab file, and loopback.
std::vector<std::string> HostsOf(const igms::config::LabConfig* config, const std::string& name,
                                 std::vector<std::string> extra) {
  std::set<std::string> hosts = {"localhost", "127.0.0.1", "::1"};
  if (config) hosts.insert(config->Get<std::string>("processes." + name + ".host", "127.0.0.1"));
  hosts.insert(extra.begin(), extra.end());
  return {hosts.begin(), hosts.end()};
}

int Run(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string dir, config_file;
  std::vector<std::string> hosts, positional;
  int days = -1;
  bool renew = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw std::runtime_error(a + " needs a value");
      return args[++i];
    };
    try {
      if (a == "--dir") {
        dir = value();
      } else if (a == "--config") {
        config_file = value();
      } else if (a == "--host") {
        hosts.push_back(value());
      } else if (a == "--days") {
        days = std::stoi(value());
      } else if (a == "--renew") {
        renew = true;
      } else if (a == "-h" || a == "--help") {
        return Usage("");
      } else if (a == "--version") {
        std::cout << igms::version::Line("igms-certs") << "\n";
        return igms::kExitOk;
      } else if (!a.empty() && a[0] == '-') {
        return Usage("unknown option " + a);
      } else {
        positional.push_back(a);
      }
    } catch (const std::exception& e) {
      return Usage(e.what());
    }
  }
  if (positional.empty()) return Usage("say what to do: init, issue, lab or show");
  const std::string verb = positional[0];
  try {
    std::optional<igms::config::LabConfig> config;
    if (config_file.empty()) config_file = igms::EnvironmentVariable("IGMS_CONFIG").value_or("");
    if (!config_file.empty()) config = igms::config::LabConfig::Load(config_file);
    if (dir.empty()) {
      dir = config ? igms::config::SecurityOf(*config, "").certs_dir : "certs";
    }
    if (verb == "init") {
      if (!igms::certs::InitFolder(dir, days > 0 ? days : 3650)) {
        std::cout << "igms certs: " << dir << " has an authority already (kept)\n";
      } else {
        std::cout << "igms certs: made the lab's authority in " << dir << "\n";
      }
      return igms::kExitOk;
    }
    if (verb == "issue") {
      if (positional.size() != 2) return Usage("issue takes one NAME");
      const std::string name = positional[1];
      if (config && name != kDiagnosticName) {
        const auto names = config->ProcessNames();
        if (std::find(names.begin(), names.end(), name) == names.end()) {
          std::cerr << "igms certs: " << config_file << " has no processes." << name
                    << " (a certificate is named by its process, or igmsctl)\n";
          return igms::kExitUsage;
        }
      }
      igms::certs::IssueOptions o;
      o.hosts = HostsOf(config ? &*config : nullptr, name, hosts);
      if (days > 0) o.days = days;
      igms::certs::IssueToFolder(dir, name, o);
      std::cout << "igms certs: issued " << igms::certs::CertFile(dir, name) << " and its key\n";
      return igms::kExitOk;
    }
    if (verb == "lab") {
      if (!config) return Usage("lab needs --config FILE");
      if (igms::certs::InitFolder(dir, 3650))
        std::cout << "igms certs: made the lab's authority in " << dir << "\n";
      std::vector<std::string> names = config->ProcessNames();
      names.push_back(kDiagnosticName);
      const auto now = static_cast<std::int64_t>(std::time(nullptr));
      int issued = 0;
      for (const auto& name : names) {
        const std::string cert = igms::certs::CertFile(dir, name);
        if (!renew && std::filesystem::exists(cert) &&
            std::filesystem::exists(igms::certs::KeyFile(dir, name))) {
          const Info info = igms::certs::Describe(igms::certs::ReadFile(cert));
          // Good for more than a week: kept.
          if (info.not_after_unix - now > std::int64_t{7} * 86400) continue;
        }
        igms::certs::IssueOptions o;
        o.hosts = HostsOf(&*config, name, hosts);
        if (days > 0) o.days = days;
        igms::certs::IssueToFolder(dir, name, o);
        ++issued;
      }
      std::cout << "igms certs: " << dir << ": " << issued << " issued, " << names.size() - issued
                << " kept\n";
      return igms::kExitOk;
    }
    if (verb == "show") {
      std::string what = positional.size() > 1 ? positional[1] : "";
      if (what.empty()) {
        Show(igms::certs::AuthorityCert(dir));
        for (const auto& e : std::filesystem::directory_iterator(dir)) {
          if (e.path().extension() == ".crt" && e.path().filename() != "ca.crt")
            Show(e.path().string());
        }
      } else {
        Show(std::filesystem::exists(what) ? what : igms::certs::CertFile(dir, what));
      }
      return igms::kExitOk;
    }
    return Usage("unknown command " + verb);
  } catch (const std::exception& e) {
    std::cerr << "igms certs: " << e.what() << "\n";
    return igms::kExitFailure;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Run catches what its commands throw; this catches the rest (copying the arguments, a
  // failed write of a message), so no exception ends the program without a word.
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "igms certs: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "igms certs: an unknown error\n";
  }
  return igms::kExitFailure;
}
