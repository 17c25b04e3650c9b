// libFuzzer target: garbage to the TLS handshake path (common/net/tls.h), on the server's
// side (as a client's first flight) and on the client's (as the server's answer to a
// ClientHello). Neither side may crash, leak or hang; each must fail with a reason or
// want more bytes. The certificates are made once, in memory, by common/certs.
// fuzz_seeds/fuzz_tls_handshake starts it from a real ClientHello (first byte 1: to the
// server) and a real server flight (first byte 0: to the client).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "common/certs/certs.h"
#include "common/net/tls.h"

namespace {

using igms::net::TlsContext;
using igms::net::TlsEngine;
using igms::net::TlsOptions;

TlsOptions Options(const igms::certs::Pem& ca, const igms::certs::Pem& own) {
  TlsOptions o;
  o.enabled = true;
  o.ca_pem = ca.cert;
  o.cert_pem = own.cert;
  o.key_pem = own.key;
  return o;
}

struct Contexts {
  Contexts() {
    const auto ca = igms::certs::MakeAuthority("fuzz authority", 30);
    igms::certs::IssueOptions o;
    o.hosts = {"127.0.0.1"};
    server = std::make_shared<TlsContext>(Options(ca, igms::certs::Issue(ca, "video", o)),
                                          TlsContext::Role::kServer);
    client = std::make_shared<TlsContext>(Options(ca, igms::certs::Issue(ca, "control", o)),
                                          TlsContext::Role::kClient);
  }
  std::shared_ptr<TlsContext> server, client;
};

void Drive(TlsEngine& engine, const std::uint8_t* data, std::size_t size) {
  // In a few pieces, as reads from a socket come.
  std::size_t at = 0;
  const std::size_t piece = size / 3 + 1;
  while (at < size) {
    const std::size_t n = std::min(piece, size - at);
    engine.Feed(reinterpret_cast<const char*>(data + at), n);
    at += n;
    const auto step = engine.Handshake();
    std::string out;
    engine.TakeOutput(&out);
    if (step == TlsEngine::Step::kFailed) return;
    if (step == TlsEngine::Step::kDone) {
      char buf[512];
      engine.Read(buf, sizeof buf);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Contexts contexts;
  if (size == 0) return 0;
  if (data[0] & 1) {
    TlsEngine server(contexts.server, "");
    Drive(server, data + 1, size - 1);
  } else {
    TlsEngine client(contexts.client, "127.0.0.1");
    client.Handshake();  // the ClientHello
    std::string hello;
    client.TakeOutput(&hello);
    Drive(client, data + 1, size - 1);
  }
  return 0;
}
