#include "common/certs/certs.h"

#include <arpa/inet.h>
#include <openssl/bio.h>
#include <openssl/bn.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace igms::certs {

namespace {

template <class T, void (*F)(T*)>
struct Deleter {
  void operator()(T* p) const { F(p); }
};
using KeyPtr = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using CertPtr = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using BioPtr = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;

[[noreturn]] void Fail(const std::string& what) {
  std::string reason;
  while (unsigned long e = ERR_get_error()) {
    char buf[256];
    ERR_error_string_n(e, buf, sizeof buf);
    reason = buf;  // the last is the innermost
  }
  throw std::runtime_error(what + (reason.empty() ? "" : ": " + reason));
}

std::string Drain(BIO* bio) {
  char* data = nullptr;
  const long n = BIO_get_mem_data(bio, &data);
  return std::string(data, static_cast<std::size_t>(n));
}

KeyPtr NewKey() {
  KeyPtr key(EVP_EC_gen("P-256"));
  if (!key) Fail("cannot make an EC key");
  return key;
}

KeyPtr ParseKey(const std::string& pem) {
  BioPtr bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  KeyPtr key(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
  if (!key) Fail("not a PEM private key");
  return key;
}

CertPtr ParseCert(const std::string& pem) {
  BioPtr bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  CertPtr cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
  if (!cert) Fail("not a PEM certificate");
  return cert;
}

bool ValidName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.')
      return false;
  }
  return true;
}

bool IsIp(const std::string& host) {
  unsigned char buf[16];
  return inet_pton(AF_INET, host.c_str(), buf) == 1 || inet_pton(AF_INET6, host.c_str(), buf) == 1;
}

void AddExtension(X509* cert, X509* issuer, int nid, const std::string& value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value.c_str());
  if (!ext) Fail("cannot add the extension " + value);
  X509_add_ext(cert, ext, -1);
  X509_EXTENSION_free(ext);
}

Pem Sign(X509* cert, EVP_PKEY* key, EVP_PKEY* signer) {
  if (X509_sign(cert, signer, EVP_sha256()) == 0) Fail("cannot sign the certificate");
  BioPtr k(BIO_new(BIO_s_mem())), c(BIO_new(BIO_s_mem()));
  if (!PEM_write_bio_PrivateKey(k.get(), key, nullptr, nullptr, 0, nullptr, nullptr) ||
      !PEM_write_bio_X509(c.get(), cert)) {
    Fail("cannot write PEM");
  }
  return {Drain(k.get()), Drain(c.get())};
}

CertPtr NewCert(const std::string& name, EVP_PKEY* key, std::int64_t start, std::int64_t life) {
  CertPtr cert(X509_new());
  X509_set_version(cert.get(), 2);
  std::unique_ptr<BIGNUM, Deleter<BIGNUM, BN_free>> serial(BN_new());
  BN_rand(serial.get(), 120, BN_RAND_TOP_ANY, BN_RAND_BOTTOM_ANY);
  BN_to_ASN1_INTEGER(serial.get(), X509_get_serialNumber(cert.get()));
  X509_gmtime_adj(X509_getm_notBefore(cert.get()), static_cast<long>(start));
  X509_gmtime_adj(X509_getm_notAfter(cert.get()), static_cast<long>(start + life));
  X509_set_pubkey(cert.get(), key);
  X509_NAME* subject = X509_get_subject_name(cert.get());
  X509_NAME_add_entry_by_txt(subject, "O", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>("IGMS lab"), -1, -1, 0);
  X509_NAME_add_entry_by_txt(subject, "CN", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>(name.c_str()), -1, -1, 0);
  return cert;
}

std::int64_t ToUnix(const ASN1_TIME* t) {
  std::tm tm{};
  if (!ASN1_TIME_to_tm(t, &tm)) return 0;
  return static_cast<std::int64_t>(timegm(&tm));
}

std::string CommonName(X509_NAME* name) {
  char buf[256] = {0};
  if (X509_NAME_get_text_by_NID(name, NID_commonName, buf, sizeof buf) < 0) return "";
  return buf;
}

}  // namespace

Pem MakeAuthority(const std::string& name, int days) {
  KeyPtr key = NewKey();
  CertPtr cert = NewCert(name, key.get(), -60, static_cast<std::int64_t>(days) * 86400);
  X509_set_issuer_name(cert.get(), X509_get_subject_name(cert.get()));
  AddExtension(cert.get(), cert.get(), NID_basic_constraints, "critical,CA:TRUE,pathlen:0");
  AddExtension(cert.get(), cert.get(), NID_key_usage, "critical,keyCertSign,cRLSign");
  AddExtension(cert.get(), cert.get(), NID_subject_key_identifier, "hash");
  return Sign(cert.get(), key.get(), key.get());
}

Pem Issue(const Pem& authority, const std::string& name, const IssueOptions& options) {
  if (!ValidName(name)) {
    throw std::runtime_error("'" + name + "' is not a valid name (letters, digits, - _ .)");
  }
  KeyPtr ca_key = ParseKey(authority.key);
  CertPtr ca = ParseCert(authority.cert);
  KeyPtr key = NewKey();
  const std::int64_t life =
      options.life_s != 0 ? options.life_s : static_cast<std::int64_t>(options.days) * 86400;
  CertPtr cert = NewCert(name, key.get(), options.start_offset_s, life);
  X509_set_issuer_name(cert.get(), X509_get_subject_name(ca.get()));
  AddExtension(cert.get(), ca.get(), NID_basic_constraints, "critical,CA:FALSE");
  AddExtension(cert.get(), ca.get(), NID_key_usage, "critical,digitalSignature");
  AddExtension(cert.get(), ca.get(), NID_ext_key_usage, "serverAuth,clientAuth");
  AddExtension(cert.get(), ca.get(), NID_authority_key_identifier, "keyid:always");
  std::string san = "DNS:" + name;
  for (const auto& host : options.hosts) {
    if (host.empty() || (host.find_first_of(",: ") != std::string::npos && !IsIp(host))) {
      throw std::runtime_error("'" + host + "' is not a host name or address");
    }
    san += (IsIp(host) ? ",IP:" : ",DNS:") + host;
  }
  AddExtension(cert.get(), ca.get(), NID_subject_alt_name, san);
  return Sign(cert.get(), key.get(), ca_key.get());
}

Info Describe(const std::string& cert_pem) {
  CertPtr cert = ParseCert(cert_pem);
  Info info;
  info.subject = CommonName(X509_get_subject_name(cert.get()));
  info.issuer = CommonName(X509_get_issuer_name(cert.get()));
  info.not_before_unix = ToUnix(X509_get0_notBefore(cert.get()));
  info.not_after_unix = ToUnix(X509_get0_notAfter(cert.get()));
  info.is_authority = X509_check_ca(cert.get()) != 0;
  auto* names = static_cast<GENERAL_NAMES*>(
      X509_get_ext_d2i(cert.get(), NID_subject_alt_name, nullptr, nullptr));
  for (int i = 0; names && i < sk_GENERAL_NAME_num(names); ++i) {
    const GENERAL_NAME* n = sk_GENERAL_NAME_value(names, i);
    if (n->type == GEN_DNS) {
      const auto* s = n->d.dNSName;
      info.hosts.emplace_back(reinterpret_cast<const char*>(ASN1_STRING_get0_data(s)),
                              static_cast<std::size_t>(ASN1_STRING_length(s)));
    } else if (n->type == GEN_IPADD) {
      const auto* s = n->d.iPAddress;
      char text[INET6_ADDRSTRLEN] = {0};
      const int family = ASN1_STRING_length(s) == 4 ? AF_INET : AF_INET6;
      inet_ntop(family, ASN1_STRING_get0_data(s), text, sizeof text);
      info.hosts.emplace_back(text);
    }
  }
  GENERAL_NAMES_free(names);
  return info;
}

std::string AuthorityCert(const std::string& dir) { return dir + "/ca.crt"; }
std::string AuthorityKey(const std::string& dir) { return dir + "/ca.key"; }
std::string CertFile(const std::string& dir, const std::string& name) {
  return dir + "/" + name + ".crt";
}
std::string KeyFile(const std::string& dir, const std::string& name) {
  return dir + "/" + name + ".key";
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteFile(const std::string& path, const std::string& text, bool secret) {
  const std::string tmp = path + ".tmp";
  std::remove(tmp.c_str());
  {
    // Created with the final mode, so a key is never readable by others, not even briefly.
    const mode_t old = umask(secret ? 077 : 022);
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    umask(old);
    if (!out) throw std::runtime_error("cannot write " + path);
    out << text;
    if (!out.flush()) throw std::runtime_error("cannot write " + path);
  }
  chmod(tmp.c_str(), secret ? 0600 : 0644);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot write " + path);
}

Pem LoadAuthority(const std::string& dir) {
  if (!std::filesystem::exists(AuthorityKey(dir))) {
    throw std::runtime_error("no authority in " + dir + " (igms certs init --dir " + dir + ")");
  }
  return {ReadFile(AuthorityKey(dir)), ReadFile(AuthorityCert(dir))};
}

bool InitFolder(const std::string& dir, int days) {
  if (std::filesystem::exists(AuthorityKey(dir))) return false;
  std::filesystem::create_directories(dir);
  std::filesystem::permissions(dir, std::filesystem::perms::owner_all);
  const Pem ca = MakeAuthority("IGMS lab authority", days);
  WriteFile(AuthorityKey(dir), ca.key, true);
  WriteFile(AuthorityCert(dir), ca.cert, false);
  return true;
}

void IssueToFolder(const std::string& dir, const std::string& name, const IssueOptions& options) {
  const Pem pem = Issue(LoadAuthority(dir), name, options);
  WriteFile(KeyFile(dir, name), pem.key, true);
  WriteFile(CertFile(dir, name), pem.cert, false);
}

}  // namespace igms::certs
