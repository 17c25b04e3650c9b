// TLS 1.3 with mutual certificates for common/net (docs/security.md).
//
// TlsContext holds one side's settings: the lab's authority, this process's certificate and
// key, TLS 1.3 only, peers verified. TlsStream runs OpenSSL over buffers of its own beside an
// Asio socket, on the socket's strand: ciphertext goes to the socket in one write for
// everything queued (a burst of small frames, or a 500 KB frame's many records), rather
// than one system call per TLS record as Asio's ssl::stream makes; reads take up to
// 256 KB of records at once on a busy connection (one record's room on an idle one).
// The socket reads into the engine's input buffer and OpenSSL's records are appended to its
// output string (a BIO of our own, not OpenSSL's memory BIOs): no copy of the ciphertext
// in between, which on a 500 KB frame cost as much as the encryption.
#pragma once

#include <utility>
//
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

typedef struct ssl_ctx_st SSL_CTX;
typedef struct ssl_st SSL;
typedef struct bio_st BIO;

namespace igms::net {

struct TlsOptions {
  bool enabled = false;
  std::string ca_file;    // the lab's authority: peers must be signed by it
  std::string cert_file;  // this side's certificate
  std::string key_file;   // and its key
  // The same, as PEM text, instead of files (the handshake fuzzer and tests).
  std::string ca_pem, cert_pem, key_pem;

  // ca.crt, NAME.crt and NAME.key in a lab's certificate folder.
  static TlsOptions FromFolder(const std::string& dir, const std::string& name);
  // The process's settings (config::ProcessSecurity(): lab.tls, lab.certs, its name).
  static TlsOptions ForProcess();
  // ForProcess with another certificate of the same folder (igmsctl --as NAME).
  static TlsOptions ForProcessAs(const std::string& name);
};

class TlsContext {
 public:
  enum class Role { kServer, kClient };
  // Throws std::runtime_error naming the file and OpenSSL's reason.
  TlsContext(const TlsOptions& options, Role role);
  ~TlsContext();
  TlsContext(const TlsContext&) = delete;
  TlsContext& operator=(const TlsContext&) = delete;

  SSL_CTX* get() const { return ctx_; }
  Role role() const { return role_; }
  // This side's certificate: its name (CN) and when it expires.
  const std::string& name() const { return name_; }
  std::int64_t not_after_unix() const { return not_after_unix_; }
  // A warning for a person when this side's certificate or the authority expires within
  // `within` (or has expired), else empty.
  std::string ExpiryWarning(std::chrono::seconds within) const;

 private:
  SSL_CTX* ctx_ = nullptr;
  Role role_;
  std::string name_;
  std::string source_;
  std::int64_t not_after_unix_ = 0;
  std::int64_t ca_not_after_unix_ = 0;
};

// The TLS state machine over memory buffers, with no socket: what the stream and the
// handshake fuzzer share.
class TlsEngine {
 public:
  // `host`: for a client, the host it dialled, checked against the server's certificate.
  TlsEngine(std::shared_ptr<const TlsContext> context, const std::string& host);
  ~TlsEngine();
  TlsEngine(const TlsEngine&) = delete;
  TlsEngine& operator=(const TlsEngine&) = delete;

  enum class Step { kDone, kWantRead, kFailed };
  // Ciphertext from the peer (a copy; the stream reads into InputRoom instead).
  void Feed(const char* data, std::size_t n);
  // Room for at least n bytes of ciphertext, and its size; CommitInput(k) once k came.
  // The room stays valid until the next InputRoom (reads between take only from before it).
  char* InputRoom(std::size_t n);
  std::size_t InputRoomSize() const { return in_capacity_ - in_end_; }
  void CommitInput(std::size_t n);
  // True when a Read may give plaintext without more ciphertext: whole or partial records
  // are here, or decrypted bytes wait. False spares a call that would only want more.
  bool HasBufferedInput() const;
  Step Handshake();
  // Decrypts into out; >0 bytes, 0 when it needs more ciphertext, -1 at the peer's
  // close_notify, -2 on an error (error()).
  long Read(char* out, std::size_t n);
  // Encrypts all of data (appends the records to the output).
  bool Write(const char* data, std::size_t n);
  // Moves the ciphertext to send into *out (appends); true when there was some.
  bool TakeOutput(std::string* out);
  bool HasOutput() const { return !sink_->empty(); }
  // Records go straight onto the end of *sink from now on (the stream's write queue, so a
  // large frame's ciphertext is written once and the strings keep their capacity);
  // TakeOutput(sink) then only says whether there is some.
  void SetOutput(std::string* sink) { sink_ = sink; }
  // Queues close_notify.
  void Close();
  // The peer certificate's CN once the handshake is done ("" without one).
  std::string PeerName() const;
  // Why the last step failed, for a person.
  const std::string& error() const { return error_; }
  // True once the first bytes from the peer did not look like TLS at all.
  bool peer_spoke_plaintext() const { return plaintext_; }

 private:
  void SetError(int ret, const char* during);

  struct BioAccess;  // the BIO's callbacks

  std::shared_ptr<const TlsContext> context_;
  SSL* ssl_ = nullptr;
  // From the peer: [in_begin_, in_end_) not yet taken by OpenSSL. Not zero-filled.
  std::unique_ptr<char[]> in_;
  std::size_t in_capacity_ = 0, in_begin_ = 0, in_end_ = 0;
  std::string out_;  // to the peer, unless SetOutput named another string
  std::string* sink_ = &out_;
  bool first_bytes_seen_ = false;
  bool plaintext_ = false;
  std::string error_;
};

// A TlsEngine beside a connected socket. Every method runs on the socket's strand, but
// TryDirectWrite.
class TlsStream : public std::enable_shared_from_this<TlsStream> {
 public:
  using Socket = boost::asio::ip::tcp::socket;
  using Done = std::function<void(const std::string& error)>;  // "" on success
  using ReadDone = std::function<void(const std::string& error, std::size_t n)>;

  TlsStream(Socket& socket, std::shared_ptr<const TlsContext> context, const std::string& host);

  // Runs the handshake to its end; the error names the cause for a person.
  void AsyncHandshake(Done done);
  // At least one byte of plaintext into out, or an error ("eof" at the peer's close).
  void AsyncReadSome(char* out, std::size_t n, ReadDone done);
  // Encrypts now; `done` runs once the ciphertext has been handed to the kernel. Writes
  // made while one is on the socket go out together in the next.
  void AsyncWrite(const char* data, std::size_t n, Done done);
  // Encrypts without a completion (the caller gathers several, then Flush).
  bool Encrypt(const char* data, std::size_t n);
  void Flush(Done done);
  // From any thread: encrypts and sends a frame at once when nothing else is being written
  // (a client's call skips the hop to its network thread). False: use the strand.
  bool TryDirectWrite(const std::string& frame);
  // close_notify, best effort; the socket stays the caller's to close.
  void Shutdown();

  std::string PeerName() const { return engine_.PeerName(); }
  TlsEngine& engine() { return engine_; }

 private:
  void ReadCiphertext(std::function<void(const std::string&)> then);
  void StartWrite();
  std::size_t DecryptLocked(char* out, std::size_t n, std::string* error);

  Socket& socket_;
  // The engine and the write state are the strand's, but for TryDirectWrite from a
  // caller's thread: the lock makes the two take turns (recursive: reads flush).
  std::recursive_mutex mutex_;
  TlsEngine engine_;
  std::size_t read_room_;           // one record's room when idle, growing while reads fill it
  std::string pending_;             // ciphertext not yet on the socket
  std::vector<Done> pending_done_;  // completions of the writes in pending_
  std::string flight_;              // ciphertext being written
  std::vector<Done> flight_done_;
  bool writing_ = false;
  std::string write_error_;
};

// Classifies a handshake failure for the peer's log: "no certificate", "another
// authority", "expired", ... with OpenSSL's words after it.
std::string ExplainTlsError(const std::string& openssl_reason, bool server_side);

}  // namespace igms::net
