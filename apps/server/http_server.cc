// The HTTP side of `rigel serve` (http_server.h).

#include "http_server.h"

#include <sys/socket.h>

#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <iostream>
#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

namespace rigel::server {
namespace {

// Connections the kernel queues before the server accepts them (the
// library's own is 5, fixed when Debian built it).
constexpr int kListenBacklog = 128;
// Connections served at once, each on its own thread; more wait for one.
constexpr std::size_t kMaxConnections = 256;
// A kept-alive connection that sends no new request is closed after this.
constexpr time_t kIdleSeconds = 5;
// A request whose bytes stop coming (or an answer the client stops
// reading) is dropped after this.
constexpr time_t kStallSeconds = 10;

std::string json_error(const std::string& message, const std::string& field = {}) {
  Json body{{"error", message}};
  if (!field.empty()) body["field"] = field;
  return body.dump(-1, ' ', false, Json::error_handler_t::replace);
}

void refuse(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(json_error(message), "application/json");
}

// Compares in time independent of where the strings differ.
bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// One thread per open connection, made when every thread is busy, up to
// kMaxConnections (cpp-httplib's pool has a fixed 8 threads, each held by a
// connection for as long as it is kept alive: 8 idle connections stalled
// everyone else).
class ConnectionThreads : public httplib::TaskQueue {
 public:
  explicit ConnectionThreads(std::size_t max) : max_(max) {}
  ~ConnectionThreads() override = default;

  void enqueue(std::function<void()> fn) override {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(fn));
    if (jobs_.size() > idle_ && threads_.size() < max_) threads_.emplace_back([this] { work(); });
    else cond_.notify_one();
  }

  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      shutdown_ = true;
    }
    cond_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

 private:
  void work() {
    for (;;) {
      std::function<void()> fn;
      {
        std::unique_lock lock(mutex_);
        ++idle_;
        cond_.wait(lock, [this] { return !jobs_.empty() || shutdown_; });
        --idle_;
        if (jobs_.empty()) return;  // shut down
        fn = std::move(jobs_.front());
        jobs_.pop_front();
      }
      fn();
    }
  }

  const std::size_t max_;
  std::mutex mutex_;
  std::condition_variable cond_;
  std::list<std::function<void()>> jobs_;
  std::vector<std::thread> threads_;
  std::size_t idle_ = 0;
  bool shutdown_ = false;
};

// cpp-httplib's server with the listening socket's backlog widened: its
// socket is listening with a backlog of 5 once bound; listen() again on a
// listening socket sets the new backlog (Linux, POSIX).
class Server : public httplib::Server {
 public:
  bool widen_backlog() { return ::listen(svr_sock_.load(), kListenBacklog) == 0; }
};

// Why a request's framing is refused before its body is read: a
// Content-Length that is not one decimal length, one over the body limit,
// a transfer coding other than chunked, or both at once (the ways one
// request is read as two). Answered at once, and the connection closed.
std::optional<std::pair<int, std::string>> framing_error(const httplib::Request& req) {
  const std::size_t lengths = req.get_header_value_count("Content-Length");
  const bool chunked = req.has_header("Transfer-Encoding");
  if (chunked) {
    if (lower(trim(req.get_header_value("Transfer-Encoding"))) != "chunked" || req.get_header_value_count("Transfer-Encoding") > 1)
      return std::pair{400, "Transfer-Encoding: '" + req.get_header_value("Transfer-Encoding") + "': only chunked is understood"};
    if (lengths > 0) return std::pair{400, "Content-Length and Transfer-Encoding together: send one"};
  }
  std::string length;
  for (std::size_t i = 0; i < lengths; ++i) {
    const std::string v = trim(req.get_header_value("Content-Length", i));
    if (v.empty() || !std::all_of(v.begin(), v.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return std::pair{400, "Content-Length: '" + v + "' is not a length in bytes"};
    if (i > 0 && v != length) return std::pair{400, "Content-Length given twice, differently"};
    length = v;
  }
  if (!length.empty() && (length.size() > 18 || std::stoull(length) > kMaxBody))
    return std::pair{413, "the body is over " + std::to_string(kMaxBody) + " bytes"};
  return std::nullopt;
}

// ---- static files ------------------------------------------------------------

std::string mime_type(const fs::path& path) {
  static const std::map<std::string, std::string> kTypes = {
      {".html", "text/html"},       {".htm", "text/html"},         {".js", "text/javascript"},
      {".mjs", "text/javascript"},  {".css", "text/css"},          {".json", "application/json"},
      {".map", "application/json"}, {".glb", "model/gltf-binary"}, {".gltf", "model/gltf+json"},
      {".svg", "image/svg+xml"},    {".png", "image/png"},         {".jpg", "image/jpeg"},
      {".jpeg", "image/jpeg"},      {".ico", "image/x-icon"},      {".wasm", "application/wasm"},
      {".txt", "text/plain"},       {".woff2", "font/woff2"},      {".woff", "font/woff"},
  };
  auto it = kTypes.find(lower(path.extension().string()));
  return it == kTypes.end() ? "application/octet-stream" : it->second;
}

bool compressible(const std::string& mime) {
  return mime.rfind("text/", 0) == 0 || mime == "application/json" || mime == "image/svg+xml" ||
         mime == "model/gltf+json" || mime == "application/wasm";
}

// FNV-1a, 64 bits: the content's tag.
std::string content_tag(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  std::ostringstream out;
  out << std::hex << h;
  return out.str();
}

// A static file as served: read once per version of it on disk (size and
// modification time), compressed once.
struct StaticFile {
  std::uintmax_t size = 0;
  fs::file_time_type mtime;
  std::string etag;       // of the bytes as they are
  std::string gzip_etag;  // of the gzip-encoded bytes
  std::shared_ptr<const std::string> bytes;
  std::shared_ptr<const std::string> gzip;  // null: not worth compressing
};

// Whether an If-None-Match header names `etag` (or is "*").
bool etag_matches(const std::string& header, const std::string& etag) {
  std::stringstream ss(header);
  for (std::string item; std::getline(ss, item, ',');) {
    item = trim(item);
    if (item.rfind("W/", 0) == 0) item = item.substr(2);
    if (item == "*" || item == etag) return true;
  }
  return false;
}

bool accepts_gzip(const httplib::Request& req) {
  std::stringstream ss(lower(req.get_header_value("Accept-Encoding")));
  for (std::string item; std::getline(ss, item, ',');) {
    const std::string coding = trim(item.substr(0, item.find(';')));
    if (coding != "gzip") continue;
    // "gzip;q=0" refuses it.
    const auto q = item.find("q=");
    return q == std::string::npos || std::strtod(item.c_str() + q + 2, nullptr) > 0;
  }
  return false;
}

}  // namespace

bool is_loopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

struct HttpServer::Impl {
  Workspace& workspace;
  ServeOptions options;
  Server http;
  int port = -1;
  // The names (lower case, IPv6 in brackets) a loopback server answers to
  // in a Host header (empty: any, off loopback).
  std::vector<std::string> hosts;
  fs::path web;  // the web folder, resolved

  std::mutex files_mutex;
  std::map<fs::path, StaticFile> files;
  std::atomic<std::size_t> compressions{0};

  Impl(Workspace& w, ServeOptions o) : workspace(w), options(std::move(o)) {
    http.new_task_queue = [] { return new ConnectionThreads(kMaxConnections); };
    http.set_payload_max_length(kMaxBody);
    http.set_keep_alive_max_count(100000);
    http.set_keep_alive_timeout(kIdleSeconds);
    // Small JSON answers go out at once: with Nagle's algorithm a drag's
    // answer waits ~40 ms for the client's delayed ACK.
    http.set_tcp_nodelay(true);
    http.set_read_timeout(kStallSeconds, 0);
    http.set_write_timeout(kStallSeconds, 0);

    // Before the body is read: framing the server cannot read right, and
    // a form upload (which cpp-httplib would parse, and refuse as 400, before
    // any handler could say why).
    http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
      auto bad = framing_error(req);
      if (!bad && req.method != "GET" && req.method != "HEAD" &&
          lower(req.get_header_value("Content-Type")).rfind("multipart/form-data", 0) == 0)
        bad = std::pair{415, "writes must be sent as Content-Type: application/json (not '" +
                                 req.get_header_value("Content-Type") + "')"};
      if (!bad) return httplib::Server::HandlerResponse::Unhandled;
      refuse(res, bad->first, bad->second);
      // The body's end is unknown: nothing more can be read from this
      // connection.
      res.set_header("Connection", "close");
      return httplib::Server::HandlerResponse::Handled;
    });

    const auto api = [this](const httplib::Request& req, httplib::Response& res) {
      // Checked once the body has been read, so a refused request leaves
      // the connection usable.
      if (refused(req, res)) return;
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
      http.Get(R"(/.*)", [this](const httplib::Request& req, httplib::Response& res) {
        if (!refused(req, res)) serve_file(req, res);
      });
    }

    // Errors with no body of ours (404 of a route, 400 of a bad request
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

  // The server's own origin for a request that came with `host` (its Host
  // header, or none).
  std::string origin_for(const std::string& host) const {
    if (!host.empty()) return "http://" + lower(host);
    const std::string h = options.host.find(':') != std::string::npos ? "[" + options.host + "]" : options.host;
    return "http://" + lower(h) + ":" + std::to_string(port);
  }

  // Refuses (answering) what may not reach this server or change its scene:
  // a Host that is not this loopback server's (DNS rebinding), and, for
  // writes, an Origin other than the server's own (another site's page),
  // a body that is not JSON (what a page may send another site without
  // asking), a missing or wrong token.
  bool refused(const httplib::Request& req, httplib::Response& res) const {
    const std::string host = lower(trim(req.get_header_value("Host")));
    if (!host.empty() && !hosts.empty()) {
      // NAME or NAME:PORT, NAME an IPv6 address in brackets.
      const auto colon = host.rfind(':');
      const bool has_port = colon != std::string::npos && host.find(']', colon) == std::string::npos;
      const std::string name = has_port ? host.substr(0, colon) : host;
      if (std::find(hosts.begin(), hosts.end(), name) == hosts.end() ||
          (has_port && host.substr(colon + 1) != std::to_string(port))) {
        refuse(res, 403, "Host '" + host + "' is not this server: it answers " + hosts.front() + ":" +
                             std::to_string(port) + " (a name that resolves here is not enough: DNS rebinding)");
        return true;
      }
    }
    if (req.method == "GET" || req.method == "HEAD") return false;
    if (req.has_header("Origin")) {
      const std::string origin = lower(trim(req.get_header_value("Origin")));
      if (origin != origin_for(host)) {
        refuse(res, 403, "Origin '" + origin + "' is not this server's (" + origin_for(host) +
                             "): writes from other sites' pages are refused");
        return true;
      }
    }
    const std::string type = req.get_header_value("Content-Type");
    if (lower(trim(type.substr(0, type.find(';')))) != "application/json") {
      refuse(res, 415, "writes must be sent as Content-Type: application/json" +
                           (type.empty() ? std::string(" (none given)") : " (not '" + type + "')"));
      return true;
    }
    if (!options.token.empty()) {
      std::string given = req.get_header_value("X-Rigel-Token");
      const std::string auth = req.get_header_value("Authorization");
      if (given.empty() && auth.rfind("Bearer ", 0) == 0) given = auth.substr(7);
      if (!same_secret(given, options.token)) {
        refuse(res, 401, given.empty() ? "this server needs a token for writes (Authorization: Bearer TOKEN)" : "wrong token");
        return true;
      }
    }
    return false;
  }

  // A file of the web folder: regular files inside it only (symbolic links
  // resolved, and their target inside too), compressed once per version,
  // revalidated with its ETag.
  void serve_file(const httplib::Request& req, httplib::Response& res) {
    const auto not_found = [&] { refuse(res, 404, "not found: " + req.path); };
    std::string rel = req.path;
    if (rel.empty() || rel.front() != '/' || rel.find('\0') != std::string::npos || rel.find('\\') != std::string::npos)
      return not_found();
    if (rel.back() == '/') rel += "index.html";
    fs::path p;
    std::stringstream ss(rel.substr(1));
    for (std::string seg; std::getline(ss, seg, '/');) {
      if (seg.empty()) continue;
      if (seg == "." || seg == "..") return not_found();
      p /= seg;
    }
    if (p.empty()) p = "index.html";
    std::error_code ec;
    const fs::path full = fs::canonical(web / p, ec);
    if (ec) return not_found();
    const auto [w, f] = std::mismatch(web.begin(), web.end(), full.begin(), full.end());
    if (w != web.end() || !fs::is_regular_file(full, ec)) return not_found();
    const std::uintmax_t size = fs::file_size(full, ec);
    if (ec) return not_found();
    const fs::file_time_type mtime = fs::last_write_time(full, ec);
    if (ec) return not_found();

    StaticFile file;
    {
      std::lock_guard lock(files_mutex);
      auto it = files.find(full);
      if (it != files.end() && it->second.size == size && it->second.mtime == mtime) file = it->second;
    }
    if (!file.bytes) {
      std::ifstream in(full, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      if (!in && !in.eof()) return not_found();
      file.size = size;
      file.mtime = mtime;
      auto bytes = std::make_shared<const std::string>(text.str());
      const std::string tag = content_tag(*bytes);
      file.etag = "\"" + tag + "\"";
      file.gzip_etag = "\"" + tag + "-gzip\"";
      if (compressible(mime_type(full)) && bytes->size() > 1024) {
        std::string packed;
        httplib::detail::gzip_compressor gz;
        const bool ok = gz.compress(bytes->data(), bytes->size(), true, [&](const char* d, std::size_t n) {
          packed.append(d, n);
          return true;
        });
        ++compressions;
        if (ok && packed.size() < bytes->size()) file.gzip = std::make_shared<const std::string>(std::move(packed));
      }
      file.bytes = std::move(bytes);
      std::lock_guard lock(files_mutex);
      files[full] = file;
    }

    const bool gzip = file.gzip && accepts_gzip(req);
    const std::string& etag = gzip ? file.gzip_etag : file.etag;
    // Always revalidated (the file names are not versioned): a 304 costs
    // no bytes.
    res.set_header("Cache-Control", "no-cache");
    res.set_header("ETag", etag);
    if (file.gzip) res.set_header("Vary", "Accept-Encoding");
    if (etag_matches(req.get_header_value("If-None-Match"), etag)) {
      res.status = 304;
      return;
    }
    std::shared_ptr<const std::string> body = gzip ? file.gzip : file.bytes;
    if (gzip) res.set_header("Content-Encoding", "gzip");
    // A content provider of known length: cpp-httplib sends it as it is
    // (set_content would have it compressed again, per request).
    res.set_content_provider(body->size(), mime_type(full),
                             [body](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                               sink.write(body->data() + offset, length);
                               return true;
                             });
  }
};

HttpServer::HttpServer(Workspace& workspace, ServeOptions options)
    : impl_(std::make_unique<Impl>(workspace, std::move(options))) {}

HttpServer::~HttpServer() { stop(); }

Result<int> HttpServer::bind() {
  const ServeOptions& o = impl_->options;
  if (o.port < 0 || o.port > 65535) return error(ErrorCode::kInvalidArgument, "--port " + std::to_string(o.port) + ": not a port");
  if (!is_loopback(o.host) && o.token.empty())
    return error(ErrorCode::kInvalidArgument, "--host " + o.host + ": other machines can reach it; writes need a token (--token)");
  if (!o.web_dir.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(o.web_dir / "index.html", ec))
      return error(ErrorCode::kNotFound, "--web " + o.web_dir.string() + ": no index.html there (build the web app: scripts/test or npm run build in web/)");
    impl_->web = fs::canonical(o.web_dir, ec);
    if (ec) return error(ErrorCode::kIoError, "--web " + o.web_dir.string() + ": " + ec.message());
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
  if (!impl_->http.widen_backlog()) return error(ErrorCode::kIoError, o.host + ": cannot listen with a backlog of " + std::to_string(kListenBacklog));
  impl_->hosts.clear();
  if (is_loopback(o.host)) {
    // The bound address first (the one error messages name), then the other
    // names of this machine's loopback.
    const std::string bound = lower(o.host.find(':') != std::string::npos ? "[" + o.host + "]" : o.host);
    for (const std::string& h : {bound, std::string("localhost"), std::string("127.0.0.1"), std::string("[::1]")})
      if (std::find(impl_->hosts.begin(), impl_->hosts.end(), h) == impl_->hosts.end()) impl_->hosts.push_back(h);
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

std::size_t HttpServer::compressions() const { return impl_->compressions.load(); }

}  // namespace rigel::server
