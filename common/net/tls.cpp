#include "common/net/tls.h"

#include <arpa/inet.h>
#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/ssl.h>
#include <openssl/x509v3.h>
#include <sys/socket.h>

#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "common/config/process_options.h"

namespace igms::net {

namespace asio = boost::asio;

namespace {

constexpr std::size_t kRecordBytes = 16 * 1024 + 256;  // a TLS record and its overhead
constexpr std::size_t kMaxReadBytes = std::size_t{256} * 1024;

bool IsIp(const std::string& host) {
  unsigned char buf[16];
  return inet_pton(AF_INET, host.c_str(), buf) == 1 || inet_pton(AF_INET6, host.c_str(), buf) == 1;
}

// OpenSSL's error queue as one line, emptied.
std::string TakeErrors() {
  std::string out;
  while (unsigned long e = ERR_get_error()) {
    const char* reason = ERR_reason_error_string(e);
    if (!out.empty()) out += "; ";
    out += reason ? reason : "error " + std::to_string(e);
  }
  return out;
}

std::int64_t ToUnix(const ASN1_TIME* t) {
  std::tm tm{};
  if (!t || !ASN1_TIME_to_tm(t, &tm)) return 0;
  return static_cast<std::int64_t>(timegm(&tm));
}

std::string CommonName(X509* cert) {
  if (!cert) return "";
  char buf[256] = {0};
  if (X509_NAME_get_text_by_NID(X509_get_subject_name(cert), NID_commonName, buf, sizeof buf) < 0)
    return "";
  return buf;
}

X509* PemCert(const std::string& pem) {
  BIO* bio = BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size()));
  X509* cert = PEM_read_bio_X509(bio, nullptr, nullptr, nullptr);
  BIO_free(bio);
  return cert;
}

std::string Date(std::int64_t unix_s) {
  const std::time_t t = static_cast<std::time_t>(unix_s);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

}  // namespace

TlsOptions TlsOptions::FromFolder(const std::string& dir, const std::string& name) {
  TlsOptions o;
  o.enabled = true;
  o.ca_file = dir + "/ca.crt";
  o.cert_file = dir + "/" + name + ".crt";
  o.key_file = dir + "/" + name + ".key";
  return o;
}

TlsOptions TlsOptions::ForProcess() { return ForProcessAs(config::ProcessSecurity().name); }

TlsOptions TlsOptions::ForProcessAs(const std::string& name) {
  const auto& s = config::ProcessSecurity();
  if (!s.tls) return {};
  return FromFolder(s.certs_dir, name);
}

TlsContext::TlsContext(const TlsOptions& o, Role role) : role_(role) {
  source_ = o.cert_file.empty() ? "the certificate given" : o.cert_file;
  ctx_ = SSL_CTX_new(role == Role::kServer ? TLS_server_method() : TLS_client_method());
  if (!ctx_) throw std::runtime_error("cannot make a TLS context: " + TakeErrors());
  auto fail = [&](const std::string& what) {
    const std::string reason = TakeErrors();
    SSL_CTX_free(ctx_);
    ctx_ = nullptr;
    throw std::runtime_error(what + (reason.empty() ? "" : " (" + reason + ")"));
  };
  SSL_CTX_set_min_proto_version(ctx_, TLS1_3_VERSION);
  SSL_CTX_set_max_proto_version(ctx_, TLS1_3_VERSION);
  // AES-GCM first: the processors of lab workstations encrypt it in hardware.
  SSL_CTX_set_ciphersuites(
      ctx_, "TLS_AES_128_GCM_SHA256:TLS_AES_256_GCM_SHA384:TLS_CHACHA20_POLY1305_SHA256");
  // Connections are long-lived and never resumed: no session tickets to make or keep.
  SSL_CTX_set_num_tickets(ctx_, 0);
  SSL_CTX_set_session_cache_mode(ctx_, SSL_SESS_CACHE_OFF);

  if (!o.ca_pem.empty()) {
    X509* ca = PemCert(o.ca_pem);
    if (!ca || !X509_STORE_add_cert(SSL_CTX_get_cert_store(ctx_), ca)) {
      X509_free(ca);
      fail("the lab's authority is not a PEM certificate");
    }
    ca_not_after_unix_ = ToUnix(X509_get0_notAfter(ca));
    X509_free(ca);
  } else {
    if (SSL_CTX_load_verify_locations(ctx_, o.ca_file.c_str(), nullptr) != 1)
      fail("cannot read the lab's authority " + o.ca_file);
    BIO* bio = BIO_new_file(o.ca_file.c_str(), "r");
    X509* ca = bio ? PEM_read_bio_X509(bio, nullptr, nullptr, nullptr) : nullptr;
    ca_not_after_unix_ = ca ? ToUnix(X509_get0_notAfter(ca)) : 0;
    X509_free(ca);
    BIO_free(bio);
  }
  if (!o.cert_pem.empty()) {
    X509* cert = PemCert(o.cert_pem);
    const bool ok = cert && SSL_CTX_use_certificate(ctx_, cert) == 1;
    X509_free(cert);
    if (!ok) fail("the certificate is not PEM");
    BIO* bio = BIO_new_mem_buf(o.key_pem.data(), static_cast<int>(o.key_pem.size()));
    EVP_PKEY* key = PEM_read_bio_PrivateKey(bio, nullptr, nullptr, nullptr);
    BIO_free(bio);
    const bool key_ok = key && SSL_CTX_use_PrivateKey(ctx_, key) == 1;
    EVP_PKEY_free(key);
    if (!key_ok) fail("the key is not PEM");
  } else if (o.cert_file.empty() && role == Role::kClient) {
    // A client with no certificate of its own: the server will refuse it, and say so.
  } else {
    if (SSL_CTX_use_certificate_file(ctx_, o.cert_file.c_str(), SSL_FILETYPE_PEM) != 1)
      fail("cannot read the certificate " + o.cert_file + " (igms certs issue NAME)");
    if (SSL_CTX_use_PrivateKey_file(ctx_, o.key_file.c_str(), SSL_FILETYPE_PEM) != 1)
      fail("cannot read the key " + o.key_file);
  }
  X509* own = SSL_CTX_get0_certificate(ctx_);
  if (own && SSL_CTX_check_private_key(ctx_) != 1) fail("the key does not match " + source_);
  name_ = CommonName(own);
  not_after_unix_ = own ? ToUnix(X509_get0_notAfter(own)) : 0;
  // Both sides prove themselves: a server refuses a client without a certificate.
  SSL_CTX_set_verify(
      ctx_, SSL_VERIFY_PEER | (role == Role::kServer ? SSL_VERIFY_FAIL_IF_NO_PEER_CERT : 0),
      nullptr);
}

TlsContext::~TlsContext() { SSL_CTX_free(ctx_); }

std::string TlsContext::ExpiryWarning(std::chrono::seconds within) const {
  const auto now = static_cast<std::int64_t>(std::time(nullptr));
  auto say = [&](const std::string& what, std::int64_t at) -> std::string {
    if (at == 0 || at - now > within.count()) return "";
    if (at <= now) return what + " expired on " + Date(at);
    return what + " expires on " + Date(at) + ", in " + std::to_string((at - now) / 3600) +
           " hours: issue a new one (igms certs issue)";
  };
  std::string w = say("the certificate of '" + name_ + "' (" + source_ + ")", not_after_unix_);
  const std::string ca = say("the lab's authority", ca_not_after_unix_);
  if (!ca.empty()) w += (w.empty() ? "" : "; ") + ca;
  return w;
}

// ---------------------------------------------------------------------------------------

// One BIO for both directions: reads take from the engine's input buffer, writes append
// to its output string. OpenSSL's memory BIOs would add a copy each way (and zero-fill
// every growth); on a 500 KB frame those copies cost as much as AES-GCM.
struct TlsEngine::BioAccess {
  static int Read(BIO* bio, char* to, std::size_t n, std::size_t* done) {
    auto* e = static_cast<TlsEngine*>(BIO_get_data(bio));
    BIO_clear_retry_flags(bio);
    const std::size_t have = e->in_end_ - e->in_begin_;
    if (have == 0) {
      BIO_set_retry_read(bio);  // "wait for more", not the end of the stream
      *done = 0;
      return 0;
    }
    const std::size_t k = std::min(n, have);
    std::memcpy(to, e->in_.get() + e->in_begin_, k);
    e->in_begin_ += k;
    *done = k;
    return 1;
  }
  static int Write(BIO* bio, const char* from, std::size_t n, std::size_t* done) {
    auto* e = static_cast<TlsEngine*>(BIO_get_data(bio));
    BIO_clear_retry_flags(bio);
    e->sink_->append(from, n);
    *done = n;
    return 1;
  }
  static long Ctrl(BIO* bio, int cmd, long, void*) {
    auto* e = static_cast<TlsEngine*>(BIO_get_data(bio));
    switch (cmd) {
      case BIO_CTRL_FLUSH:
        return 1;
      case BIO_CTRL_PENDING:
        return e ? static_cast<long>(e->in_end_ - e->in_begin_) : 0;
      case BIO_CTRL_WPENDING:
        return e ? static_cast<long>(e->sink_->size()) : 0;
      default:
        return 0;
    }
  }
  static int Create(BIO* bio) {
    BIO_set_init(bio, 1);
    return 1;
  }
  static const BIO_METHOD* Method() {
    static BIO_METHOD* method = [] {
      BIO_METHOD* m = BIO_meth_new(BIO_get_new_index() | BIO_TYPE_SOURCE_SINK, "igms tls buffers");
      BIO_meth_set_read_ex(m, Read);
      BIO_meth_set_write_ex(m, Write);
      BIO_meth_set_ctrl(m, Ctrl);
      BIO_meth_set_create(m, Create);
      return m;
    }();
    return method;
  }
};

TlsEngine::TlsEngine(std::shared_ptr<const TlsContext> context, const std::string& host)
    : context_(std::move(context)) {
  ssl_ = SSL_new(context_->get());
  BIO* bio = BIO_new(BioAccess::Method());
  BIO_set_data(bio, this);
  SSL_set_bio(ssl_, bio, bio);  // one reference for both directions
  if (context_->role() == TlsContext::Role::kServer) {
    SSL_set_accept_state(ssl_);
  } else {
    SSL_set_connect_state(ssl_);
    if (!host.empty()) {
      if (IsIp(host)) {
        X509_VERIFY_PARAM_set1_ip_asc(SSL_get0_param(ssl_), host.c_str());
      } else {
        SSL_set1_host(ssl_, host.c_str());
        SSL_set_tlsext_host_name(ssl_, host.c_str());
      }
    }
  }
}

TlsEngine::~TlsEngine() { SSL_free(ssl_); }  // frees the BIO

void TlsEngine::Feed(const char* data, std::size_t n) {
  if (n == 0) return;
  std::memcpy(InputRoom(n), data, n);
  CommitInput(n);
}

char* TlsEngine::InputRoom(std::size_t n) {
  if (in_begin_ == in_end_) in_begin_ = in_end_ = 0;
  if (in_capacity_ - in_end_ < n && in_begin_ > 0) {
    // A partial record left over: to the front, so the room follows it.
    std::memmove(in_.get(), in_.get() + in_begin_, in_end_ - in_begin_);
    in_end_ -= in_begin_;
    in_begin_ = 0;
  }
  if (in_capacity_ - in_end_ < n) {
    const std::size_t capacity = std::max(in_end_ + n, in_capacity_ * 2);
    std::unique_ptr<char[]> bigger(new char[capacity]);
    if (in_end_ > in_begin_) std::memcpy(bigger.get(), in_.get() + in_begin_, in_end_ - in_begin_);
    in_end_ -= in_begin_;
    in_begin_ = 0;
    in_ = std::move(bigger);
    in_capacity_ = capacity;
  }
  return in_.get() + in_end_;
}

void TlsEngine::CommitInput(std::size_t n) {
  if (n == 0) return;
  const char* data = in_.get() + in_end_;
  if (!first_bytes_seen_) {
    first_bytes_seen_ = true;
    // Every TLS record starts with its type (20 to 23) and major version 3; an IGMS frame
    // starts with its length and then the envelope's first tag (0x0a).
    const auto type = static_cast<unsigned char>(data[0]);
    plaintext_ = type < 20 || type > 23 || (n >= 2 && data[1] != 0x03);
  }
  in_end_ += n;
}

bool TlsEngine::HasBufferedInput() const { return in_end_ > in_begin_ || SSL_pending(ssl_) > 0; }

void TlsEngine::SetError(int ret, const char* during) {
  const int code = SSL_get_error(ssl_, ret);
  std::string reason = TakeErrors();
  const long verify = SSL_get_verify_result(ssl_);
  if (verify != X509_V_OK) {
    reason = X509_verify_cert_error_string(verify) + (reason.empty() ? "" : " (" + reason + ")");
  }
  if (plaintext_) {
    error_ = "the peer speaks plain TCP, not TLS: lab.tls differs between the two sides";
  } else if (code == SSL_ERROR_SYSCALL && reason.empty()) {
    error_ = std::string("the connection broke during ") + during;
  } else {
    error_ = ExplainTlsError(reason, context_->role() == TlsContext::Role::kServer);
  }
}

TlsEngine::Step TlsEngine::Handshake() {
  if (plaintext_) {
    SetError(-1, "the handshake");
    return Step::kFailed;
  }
  const int r = SSL_do_handshake(ssl_);
  if (r == 1) return Step::kDone;
  const int code = SSL_get_error(ssl_, r);
  if (code == SSL_ERROR_WANT_READ) return Step::kWantRead;
  SetError(r, "the handshake");
  return Step::kFailed;
}

long TlsEngine::Read(char* out, std::size_t n) {
  const int r = SSL_read(ssl_, out, static_cast<int>(std::min<std::size_t>(n, 1u << 30)));
  if (r > 0) return r;
  const int code = SSL_get_error(ssl_, r);
  if (code == SSL_ERROR_WANT_READ) return 0;
  if (code == SSL_ERROR_ZERO_RETURN) return -1;
  SetError(r, "a read");
  return -2;
}

bool TlsEngine::Write(const char* data, std::size_t n) {
  while (n > 0) {
    const int chunk = static_cast<int>(std::min<std::size_t>(n, 1u << 30));
    const int r = SSL_write(ssl_, data, chunk);
    if (r <= 0) {
      SetError(r, "a write");
      return false;
    }
    data += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

void TlsEngine::Close() {
  if (SSL_is_init_finished(ssl_)) SSL_shutdown(ssl_);
  ERR_clear_error();
}

bool TlsEngine::TakeOutput(std::string* out) {
  if (out == sink_) return !out->empty();
  if (sink_->empty()) return false;
  out->append(*sink_);
  sink_->clear();
  return true;
}

std::string TlsEngine::PeerName() const {
  X509* peer = SSL_get0_peer_certificate(ssl_);
  return CommonName(peer);
}

std::string ExplainTlsError(const std::string& reason, bool server_side) {
  auto has = [&](const char* s) { return reason.find(s) != std::string::npos; };
  std::string what;
  if (server_side && has("alert") && !has("certificate required")) {
    what =
        "the client refused this server's certificate (another authority, expired, or not "
        "naming the host it dialled)";
  } else if (has("peer did not return a certificate") || has("certificate required")) {
    what = server_side ? "the client presented no certificate"
                       : "the server wants a certificate and this client has none";
  } else if (has("certificate has expired") || has("certificate expired")) {
    what = server_side ? "the client's certificate has expired"
                       : (has("alert") ? "the server refused this client's certificate: it has "
                                         "expired"
                                       : "the server's certificate has expired");
  } else if (has("unknown ca") || has("unable to get local issuer") || has("self-signed") ||
             has("self signed") || has("bad certificate") || has("certificate signature")) {
    if (server_side) {
      what = "the client's certificate is not signed by the lab's authority";
    } else if (has("alert")) {
      what = "the server refused this client's certificate (not signed by its authority?)";
    } else {
      what = "the server's certificate is not signed by the lab's authority";
    }
  } else if (has("mismatch")) {
    what = "the server's certificate does not name the host dialled";
  } else if (has("wrong version number") || has("packet length too long") || has("http request") ||
             has("record layer failure")) {
    what = "the peer speaks plain TCP, not TLS: lab.tls differs between the two sides";
  } else if (has("protocol version") || has("unsupported protocol")) {
    what = "the peer does not speak TLS 1.3";
  } else {
    what = "TLS failed";
  }
  return reason.empty() ? what : what + " [" + reason + "]";
}

// ---------------------------------------------------------------------------------------

TlsStream::TlsStream(Socket& socket, std::shared_ptr<const TlsContext> context,
                     const std::string& host)
    : socket_(socket), engine_(std::move(context), host), read_room_(kRecordBytes) {
  engine_.SetOutput(&pending_);
}

void TlsStream::ReadCiphertext(std::function<void(const std::string&)> then) {
  char* at = nullptr;
  std::size_t room = 0;
  {
    std::lock_guard lock(mutex_);
    at = engine_.InputRoom(read_room_);
    room = engine_.InputRoomSize();
  }
  // Straight into the engine's buffer: OpenSSL takes its records from there.
  socket_.async_read_some(asio::buffer(at, room),
                          [self = shared_from_this(), room, then = std::move(then)](
                              boost::system::error_code ec, std::size_t n) {
                            if (ec) {
                              then(ec == asio::error::eof ? "eof" : ec.message());
                              return;
                            }
                            {
                              std::lock_guard lock(self->mutex_);
                              self->engine_.CommitInput(n);
                            }
                            // An idle session keeps one record's room; a busy one grows it
                            // to take a large frame's records in few reads.
                            if (n == room && self->read_room_ < kMaxReadBytes)
                              self->read_room_ *= 4;
                            then("");
                          });
}

void TlsStream::AsyncHandshake(Done done) {
  std::lock_guard lock(mutex_);
  const auto step = engine_.Handshake();
  switch (step) {
    case TlsEngine::Step::kDone:
      // Our last flight (a client's Finished) goes out before the connection counts as up.
      Flush(std::move(done));
      return;
    case TlsEngine::Step::kFailed:
      // The alert goes to the peer, so it learns why too.
      Flush([done = std::move(done), error = engine_.error()](const std::string&) { done(error); });
      return;
    case TlsEngine::Step::kWantRead:
      if (engine_.HasOutput()) Flush(nullptr);
      ReadCiphertext([self = shared_from_this(), done = std::move(done)](const std::string& e) {
        if (!e.empty()) {
          done(e == "eof" ? "the peer closed the connection during the TLS handshake" : e);
          return;
        }
        self->AsyncHandshake(done);
      });
      return;
  }
}

// With the lock held: every whole record already here, decrypted into out (up to n).
std::size_t TlsStream::DecryptLocked(char* out, std::size_t n, std::string* error) {
  std::size_t got = 0;
  long r = 0;
  // Only while something is buffered: a call that can only want more costs as much as a
  // small record's decryption.
  while (got < n && engine_.HasBufferedInput() && (r = engine_.Read(out + got, n - got)) > 0) {
    got += static_cast<std::size_t>(r);
  }
  if (engine_.HasOutput()) Flush(nullptr);  // post-handshake messages (key updates)
  if (got == 0 && r == -1) *error = "eof";
  if (got == 0 && r == -2) *error = engine_.error();
  return got;
}

void TlsStream::AsyncReadSome(char* out, std::size_t n, ReadDone done) {
  std::string error;
  std::size_t got = 0;
  {
    std::lock_guard lock(mutex_);
    got = DecryptLocked(out, n, &error);
  }
  if (got > 0 || !error.empty()) {
    // Posted: a caller that reads again from its completion does not recurse.
    asio::post(socket_.get_executor(), [done = std::move(done), error, got] { done(error, got); });
    return;
  }
  ReadCiphertext(
      [self = shared_from_this(), out, n, done = std::move(done)](const std::string& e) mutable {
        if (!e.empty()) {
          done(e, 0);
          return;
        }
        std::string error;
        std::size_t got = 0;
        {
          std::lock_guard lock(self->mutex_);
          got = self->DecryptLocked(out, n, &error);
        }
        if (got > 0 || !error.empty()) {
          done(error, got);
        } else {
          self->AsyncReadSome(out, n, std::move(done));  // a partial record: read on
        }
      });
}

bool TlsStream::Encrypt(const char* data, std::size_t n) {
  std::lock_guard lock(mutex_);
  return engine_.Write(data, n);
}

bool TlsStream::TryDirectWrite(const std::string& frame) {
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || writing_ || !pending_.empty() || !socket_.is_open()) return false;
  // Encrypted onto the (empty) write queue, and sent from there.
  if (!engine_.Write(frame.data(), frame.size())) return false;  // the strand's write reports it
  std::string& out = pending_;
  std::size_t sent = 0;
  while (sent < out.size()) {
    const ssize_t n = ::send(socket_.native_handle(), out.data() + sent, out.size() - sent,
                             MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;  // a full socket buffer, or an error the strand's next write reports
    }
  }
  if (sent == out.size()) {
    out.clear();
  } else {
    out.erase(0, sent);  // the rest, by the strand
    asio::post(socket_.get_executor(), [self = shared_from_this()] {
      std::lock_guard lock(self->mutex_);
      self->StartWrite();
    });
  }
  return true;
}

void TlsStream::AsyncWrite(const char* data, std::size_t n, Done done) {
  std::lock_guard lock(mutex_);
  if (!engine_.Write(data, n)) {
    asio::post(socket_.get_executor(), [done = std::move(done), e = engine_.error()] { done(e); });
    return;
  }
  Flush(std::move(done));
}

void TlsStream::Flush(Done done) {
  std::lock_guard lock(mutex_);
  engine_.TakeOutput(&pending_);
  if (done) pending_done_.push_back(std::move(done));
  StartWrite();
}

// With the lock held.
void TlsStream::StartWrite() {
  if (writing_) return;
  if (pending_.empty()) {
    if (pending_done_.empty()) return;
    // Nothing left to write for these completions: they are done.
    auto dones = std::move(pending_done_);
    pending_done_.clear();
    asio::post(socket_.get_executor(), [dones = std::move(dones), e = write_error_] {
      for (const auto& d : dones) d(e);
    });
    return;
  }
  writing_ = true;
  flight_.swap(pending_);
  flight_done_.swap(pending_done_);
  asio::async_write(socket_, asio::buffer(flight_),
                    [self = shared_from_this()](boost::system::error_code ec, std::size_t) {
                      std::vector<Done> dones;
                      std::string error;
                      {
                        std::lock_guard lock(self->mutex_);
                        self->writing_ = false;
                        self->flight_.clear();
                        dones.swap(self->flight_done_);
                        if (ec) self->write_error_ = "write failed: " + ec.message();
                        error = self->write_error_;
                        if (!ec) self->StartWrite();
                      }
                      // Outside the lock: a completion may write again.
                      for (const auto& d : dones) d(error);
                    });
}

void TlsStream::Shutdown() {
  // Best effort and non-blocking: the peer learns the close was deliberate. Not while a
  // write is on the socket (the alert would land inside its records).
  std::lock_guard lock(mutex_);
  if (writing_ || !pending_.empty() || !socket_.is_open()) return;
  engine_.Close();  // onto the empty write queue
  if (pending_.empty()) return;
  [[maybe_unused]] const auto n = ::send(socket_.native_handle(), pending_.data(), pending_.size(),
                                         MSG_DONTWAIT | MSG_NOSIGNAL);
  pending_.clear();
}

}  // namespace igms::net
