// The lab's certificate authority: one authority per lab, one key and certificate per
// process, named by its entry under `processes` (docs/security.md).
//
// Keys are EC P-256 (a handshake costs a fraction of an RSA one), certificates X.509 v3
// with the name as the subject's CN and as a DNS name, plus the hosts the process is
// reached at as subject alternative names. Everything is made with OpenSSL's library, not
// its command line. Key files are written with mode 0600.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace igms::certs {

// A key and its certificate, PEM-encoded.
struct Pem {
  std::string key;
  std::string cert;
};

struct IssueOptions {
  std::vector<std::string> hosts;  // DNS names or IP addresses the holder is reached at
  int days = 365;
  // Seconds from now the certificate starts; negative back-dates it (tests make an
  // expired certificate with a start and a life in the past).
  std::int64_t start_offset_s = -60;
  std::int64_t life_s = 0;  // when non-zero, overrides days
};

// A new authority ("CN=NAME"). Throws std::runtime_error with OpenSSL's reason.
Pem MakeAuthority(const std::string& name, int days);
// A certificate for `name`, signed by `authority`.
Pem Issue(const Pem& authority, const std::string& name, const IssueOptions& options);

// What a certificate says, for `igms certs show` and the expiry warning.
struct Info {
  std::string subject;  // its CN
  std::string issuer;   // the issuer's CN
  std::vector<std::string> hosts;
  std::int64_t not_before_unix = 0;
  std::int64_t not_after_unix = 0;
  bool is_authority = false;
};
Info Describe(const std::string& cert_pem);

// Files in a lab's certificate folder: ca.crt, ca.key, NAME.crt, NAME.key.
std::string AuthorityCert(const std::string& dir);
std::string AuthorityKey(const std::string& dir);
std::string CertFile(const std::string& dir, const std::string& name);
std::string KeyFile(const std::string& dir, const std::string& name);

std::string ReadFile(const std::string& path);  // throws, naming the file
// Writes atomically; mode 0600 for keys, 0644 for certificates.
void WriteFile(const std::string& path, const std::string& text, bool secret);

// The folder's authority; throws when it has none ("run igms certs init").
Pem LoadAuthority(const std::string& dir);
// Makes the folder's authority unless it has one; true when made.
bool InitFolder(const std::string& dir, int days);
// Issues NAME into the folder with the folder's authority.
void IssueToFolder(const std::string& dir, const std::string& name, const IssueOptions& options);

}  // namespace igms::certs
