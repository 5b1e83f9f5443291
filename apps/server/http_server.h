#pragma once
// The HTTP side of `rigel serve` (cpp-httplib): the API routes go to a
// Workspace, everything else is a static file of the web app. Binding,
// connections, tokens, which requests may write (Host, Origin,
// Content-Type), framing and body limits, and the static files' caching are
// here; what a request means is not (workspace.h, docs/SERVER.md).

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "rigel/base/status.h"
#include "workspace.h"

namespace rigel::server {

struct ServeOptions {
  std::string host = "127.0.0.1";
  int port = 8080;  // 0: any free port (bind() says which)
  // The built web app (index.html, app.js, ...); empty: API only.
  std::filesystem::path web_dir;
  // Required on every POST (Authorization: Bearer T, or X-Rigel-Token: T)
  // when not empty; bind() refuses a host other than loopback without one.
  std::string token;
  // One line per request on stderr.
  bool log = false;
};

// True for 127.0.0.0/8, ::1 and "localhost": addresses no other machine reaches.
bool is_loopback(const std::string& host);

class HttpServer {
 public:
  HttpServer(Workspace& workspace, ServeOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Binds the socket; returns the port (the one chosen when options.port is
  // 0). kIoError naming the address when the port is taken or refused.
  Result<int> bind();
  // Serves until stop() (from another thread or a signal handler's thread).
  Status run();
  void stop();

  // How many times a static file of the web app was compressed (once per
  // file and version of it: the compressed bytes are kept). For tests.
  std::size_t compressions() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rigel::server
