// The HTTP side of `rigel serve` (http_server.h).

#include "http_server.h"

#include <httplib.h>

#include <chrono>
#include <iostream>

namespace rigel::server {
namespace {

std::string json_error(const std::string& message, const std::string& field = {}) {
  Json body{{"error", message}};
  if (!field.empty()) body["field"] = field;
  return body.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Compares in time independent of where the strings differ.
bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

}  // namespace

bool is_loopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

struct HttpServer::Impl {
  Workspace& workspace;
  ServeOptions options;
  httplib::Server http;
  int port = -1;

  Impl(Workspace& w, ServeOptions o) : workspace(w), options(std::move(o)) {
    http.set_payload_max_length(kMaxBody);
    http.set_keep_alive_max_count(100000);
    // Small JSON answers go out at once: with Nagle's algorithm a drag's
    // answer waits ~40 ms for the client's delayed ACK.
    http.set_tcp_nodelay(true);
    http.set_read_timeout(30, 0);
    http.set_write_timeout(30, 0);

    const auto api = [this](const httplib::Request& req, httplib::Response& res) {
      // Writes need the token when there is one. Checked here, once the body
      // has been read, so a refused request leaves the connection usable.
      if (!options.token.empty() && req.method != "GET" && req.method != "HEAD") {
        std::string given = req.get_header_value("X-Rigel-Token");
        const std::string auth = req.get_header_value("Authorization");
        if (given.empty() && auth.rfind("Bearer ", 0) == 0) given = auth.substr(7);
        if (!same_secret(given, options.token)) {
          res.status = 401;
          res.set_content(json_error(given.empty() ? "this server needs a token for writes (Authorization: Bearer TOKEN)"
                                                   : "wrong token"),
                          "application/json");
          return;
        }
      }
      Request r;
      r.method = req.method;
      r.path = req.path;
      for (const auto& [k, v] : req.params) r.query[k] = v;
      r.body = req.body;
      Response answer = workspace.handle(r);
      res.status = answer.status;
      res.set_header("Cache-Control", "no-store");
      res.set_content(std::move(answer.body), answer.content_type.c_str());
    };
    const char* pattern = R"(/api/.*)";
    http.Get(pattern, api);
    http.Post(pattern, api);
    http.Put(pattern, api);
    http.Delete(pattern, api);
    http.Patch(pattern, api);

    if (!options.web_dir.empty()) {
      http.set_file_extension_and_mimetype_mapping("js", "text/javascript");
      http.set_file_extension_and_mimetype_mapping("mjs", "text/javascript");
      http.set_file_extension_and_mimetype_mapping("map", "application/json");
      http.set_file_extension_and_mimetype_mapping("glb", "model/gltf-binary");
      // cpp-httplib refuses paths that climb out of the mount (".." after
      // decoding) before touching the file system.
      http.set_mount_point("/", options.web_dir.string());
    }

    // Errors with no body of ours (413, 404 of a file, 400 of a bad request
    // line) still answer JSON with a message.
    http.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return;
      std::string message;
      switch (res.status) {
        case 404: message = "not found: " + req.path; break;
        case 413: message = "the body is over " + std::to_string(kMaxBody) + " bytes"; break;
        case 400: message = "bad request"; break;
        default: message = "error " + std::to_string(res.status); break;
      }
      res.set_content(json_error(message), "application/json");
    });
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
      std::string what = "unknown";
      try {
        if (ep) std::rethrow_exception(ep);
      } catch (const std::exception& e) {
        what = e.what();
      } catch (...) {
      }
      res.status = 500;
      res.set_content(json_error("internal error: " + what), "application/json");
    });
    if (options.log) {
      http.set_logger([](const httplib::Request& req, const httplib::Response& res) {
        std::cerr << "rigel serve: " << req.method << " " << req.path << " " << res.status << "\n";
      });
    }
  }
};

HttpServer::HttpServer(Workspace& workspace, ServeOptions options)
    : impl_(std::make_unique<Impl>(workspace, std::move(options))) {}

HttpServer::~HttpServer() { stop(); }

Result<int> HttpServer::bind() {
  const ServeOptions& o = impl_->options;
  if (o.port < 0 || o.port > 65535) return error(ErrorCode::kInvalidArgument, "--port " + std::to_string(o.port) + ": not a port");
  if (!o.web_dir.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(o.web_dir / "index.html", ec))
      return error(ErrorCode::kNotFound, "--web " + o.web_dir.string() + ": no index.html there (build the web app: scripts/test or npm run build in web/)");
  }
  if (o.port == 0) {
    const int port = impl_->http.bind_to_any_port(o.host);
    if (port < 0) return error(ErrorCode::kIoError, o.host + ": cannot bind a port");
    impl_->port = port;
  } else {
    if (!impl_->http.bind_to_port(o.host, o.port))
      return error(ErrorCode::kIoError, o.host + ":" + std::to_string(o.port) + ": cannot bind (in use, or not an address of this machine)");
    impl_->port = o.port;
  }
  return impl_->port;
}

Status HttpServer::run() {
  if (impl_->port < 0) {
    auto p = bind();
    if (!p) return p.status();
  }
  if (!impl_->http.listen_after_bind()) return error(ErrorCode::kIoError, "the server stopped listening");
  return Status::ok();
}

void HttpServer::stop() {
  if (impl_ && impl_->http.is_running()) impl_->http.stop();
}

}  // namespace rigel::server
