// `rigel serve` over real sockets on loopback: static files without path
// traversal or links out of the folder, cached and revalidated; tokens and
// the checks on who may write (Host, Origin, Content-Type); framing and body
// limits; idle connections that block no one; errors that leave the server
// serving; and a bounded load test of concurrent drags (p99 latency
// reported).

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <thread>

#include "http_server.h"
#include "server_test_util.h"

// After Eigen: <resolv.h>, which httplib includes, defines a macro `_res`
// that Eigen uses as a parameter name.
#include <httplib.h>

namespace rigel::server {
namespace {

// A running server on a free port of 127.0.0.1, stopped when it goes.
struct Running {
  Served served;
  std::unique_ptr<HttpServer> http;
  std::thread thread;
  int port = 0;

  Running(Served s, ServeOptions options) : served(std::move(s)) {
    options.port = 0;
    http = std::make_unique<HttpServer>(*served.workspace, options);
    auto p = http->bind();
    EXPECT_TRUE(p.is_ok()) << p.status().message();
    port = p.is_ok() ? *p : 0;
    thread = std::thread([this] { EXPECT_TRUE(http->run().is_ok()); });
    // Wait until it answers.
    httplib::Client c("127.0.0.1", port);
    for (int i = 0; i < 200 && !c.Get("/api/revision"); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ~Running() {
    http->stop();
    thread.join();
  }
  httplib::Client client() {
    httplib::Client c("127.0.0.1", port);
    c.set_keep_alive(true);
    c.set_tcp_nodelay(true);
    return c;
  }
};

std::string lower_copy(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

// A raw TCP connection to 127.0.0.1:port (closed when it goes), for what an
// HTTP client library will not send.
struct RawSocket {
  int fd = -1;
  explicit RawSocket(int port) {
    fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      ::close(fd);
      fd = -1;
    }
    // A safety net only: the answers below come at once or the test fails.
    timeval tv{60, 0};
    if (fd >= 0) ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~RawSocket() {
    if (fd >= 0) ::close(fd);
  }
  RawSocket(const RawSocket&) = delete;
  RawSocket& operator=(const RawSocket&) = delete;
  bool send(const std::string& bytes) const {
    return fd >= 0 && ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
  }
  // Reads until the end of the answer's headers (or the connection closes).
  std::string answer_head() const {
    std::string in;
    char buf[4096];
    while (in.find("\r\n\r\n") == std::string::npos) {
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0) break;
      in.append(buf, static_cast<std::size_t>(n));
    }
    return in;
  }
  // Still connected: the server has not closed it (nothing to read, no EOF).
  bool open() const {
    char c;
    const ssize_t n = ::recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT);
    return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK);
  }
};

// A web folder with an index page, inside a root that also holds a secret
// beside it (which no URL may reach).
struct Web {
  TempDir dir;
  fs::path web;
  Web() {
    web = dir.path() / "web";
    fs::create_directories(web / "assets");
    write_text(web / "index.html", "<!doctype html><title>rigel</title>");
    write_text(web / "assets/app.js", "console.log('rigel');");
    write_text(dir.path() / "secret.txt", "do not serve me");
  }
};

TEST(ServerHttp, ServesTheWebAppAndRefusesPathTraversal) {
  Web web;
  ServeOptions o;
  o.web_dir = web.web;
  Running r(served_character(), o);
  auto c = r.client();
  auto index = c.Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_NE(index->body.find("<title>rigel</title>"), std::string::npos);
  auto js = c.Get("/assets/app.js");
  ASSERT_TRUE(js);
  EXPECT_EQ(js->status, 200);
  EXPECT_EQ(js->get_header_value("Content-Type"), "text/javascript");
  for (const char* attack : {"/../secret.txt", "/assets/../../secret.txt", "/%2e%2e/secret.txt", "/assets/%2e%2e/%2e%2e/secret.txt",
                             "/..%2fsecret.txt", "/%2e%2e%2fsecret.txt", "//etc/passwd", "/assets/..%5c..%5csecret.txt"}) {
    auto res = c.Get(attack);
    // httplib may refuse to send some of these; a response must never leak.
    if (res) {
      EXPECT_GE(res->status, 400) << attack;
      EXPECT_LT(res->status, 500) << attack;
      EXPECT_EQ(res->body.find("do not serve me"), std::string::npos) << attack;
      EXPECT_EQ(res->body.find("root:"), std::string::npos) << attack;
    }
  }
  // Still serving.
  auto again = c.Get("/api/revision");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
}

TEST(ServerHttp, BadRequestsGet4xxWithAMessageAndTheServerGoesOn) {
  Running r(served_puppet(), {});
  auto c = r.client();
  struct Case {
    const char* path;
    std::string body;
    int status;
  };
  const std::vector<Case> cases = {
      {"/api/select", "{not json", 400},
      {"/api/select", R"({"controls": [1]})", 400},
      {"/api/select", R"({"controls": ["nobody"]})", 404},
      {"/api/drag", R"({"translate": "up"})", 400},
      {"/api/nowhere", "{}", 404},
      {"/api/select", std::string(kMaxBody + 10, 'x'), 413},
  };
  for (const Case& k : cases) {
    auto res = c.Post(k.path, k.body, "application/json");
    ASSERT_TRUE(res) << k.path;
    EXPECT_EQ(res->status, k.status) << k.path << " " << res->body;
    const Json body = Json::parse(res->body, nullptr, false);
    ASSERT_TRUE(body.is_object()) << res->body;
    EXPECT_TRUE(body.contains("error")) << res->body;
  }
  auto ok = c.Post("/api/select", R"({"controls": ["hand.L"]})", "application/json");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200) << ok->body;
}

TEST(ServerHttp, WritesNeedTheTokenWhenThereIsOne) {
  ServeOptions o;
  o.token = "s3cret";
  Running r(served_puppet(), o);
  auto c = r.client();
  const char* body = R"({"controls": ["hand.L"]})";
  auto none = c.Post("/api/select", body, "application/json");
  ASSERT_TRUE(none);
  EXPECT_EQ(none->status, 401);
  EXPECT_NE(none->body.find("token"), std::string::npos);
  auto wrong = c.Post("/api/select", httplib::Headers{{"Authorization", "Bearer nope"}}, body, "application/json");
  ASSERT_TRUE(wrong);
  EXPECT_EQ(wrong->status, 401);
  auto right = c.Post("/api/select", httplib::Headers{{"Authorization", "Bearer s3cret"}}, body, "application/json");
  ASSERT_TRUE(right);
  EXPECT_EQ(right->status, 200) << right->body;
  auto header = c.Post("/api/select", httplib::Headers{{"X-Rigel-Token", "s3cret"}}, body, "application/json");
  ASSERT_TRUE(header);
  EXPECT_EQ(header->status, 200);
  // Reads need none.
  auto read = c.Get("/api/scene");
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 200);
}

TEST(ServerHttp, LoopbackIsRecognised) {
  EXPECT_TRUE(is_loopback("127.0.0.1"));
  EXPECT_TRUE(is_loopback("localhost"));
  EXPECT_TRUE(is_loopback("::1"));
  EXPECT_FALSE(is_loopback("0.0.0.0"));
  EXPECT_FALSE(is_loopback("192.168.1.4"));
}

TEST(ServerHttp, TwoClientsSeeOneScene) {
  Running r(served_puppet(), {});
  auto a = r.client();
  auto b = r.client();
  const auto rev = Json::parse(b.Get("/api/revision")->body)["revision"].get<std::uint64_t>();
  ASSERT_EQ(a.Post("/api/select", R"({"controls": ["hand.L"]})", "application/json")->status, 200);
  ASSERT_EQ(a.Post("/api/drag", R"({"translate": [0, 0.1, 0]})", "application/json")->status, 200);
  const Json seen = Json::parse(b.Get("/api/revision")->body);
  EXPECT_EQ(seen["revision"].get<std::uint64_t>(), rev + 2);
  const Json pa = Json::parse(a.Get("/api/pose")->body), pb = Json::parse(b.Get("/api/pose")->body);
  EXPECT_EQ(pa, pb);
}

// Bounded load: 8 clients x N drags on one scene, each a full round trip
// with its JSON pose; no error allowed, p99 latency reported.
TEST(ServerHttp, LoadOfConcurrentDragsHasNoErrors) {
#ifdef RIGEL_SANITIZED_BUILD
  const int per_client = 100;
#else
  const int per_client = 2000;
#endif
  const int clients = 8;
  Running r(served_puppet(), {});
  {
    auto c = r.client();
    ASSERT_EQ(c.Post("/api/select", R"({"controls": ["hand.L"]})", "application/json")->status, 200);
    ASSERT_EQ(c.Post("/api/mode", R"({"mode": "pseudo-inverse"})", "application/json")->status, 200);
  }
  std::vector<std::vector<double>> latencies(clients);
  std::atomic<int> errors{0};
  std::vector<std::thread> threads;
  for (int k = 0; k < clients; ++k) {
    threads.emplace_back([&, k] {
      auto c = r.client();
      for (int i = 0; i < per_client; ++i) {
        const double s = ((i + k) % 2 ? 1 : -1) * 0.001;
        const std::string body = "{\"translate\": [0, " + std::to_string(s) + ", 0]}";
        const auto t0 = std::chrono::steady_clock::now();
        auto res = c.Post("/api/drag", body, "application/json");
        const auto t1 = std::chrono::steady_clock::now();
        if (!res || res->status != 200 || res->body.find("\"nodes\":{\"") == std::string::npos) ++errors;
        latencies[static_cast<std::size_t>(k)].push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      }
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(errors.load(), 0);
  std::vector<double> all;
  for (const auto& l : latencies) all.insert(all.end(), l.begin(), l.end());
  std::sort(all.begin(), all.end());
  ASSERT_EQ(all.size(), static_cast<std::size_t>(clients * per_client));
  const double p50 = all[all.size() / 2], p99 = all[all.size() * 99 / 100];
  std::printf("[ load     ] %d clients x %d drags: p50 %.3f ms, p99 %.3f ms, max %.3f ms\n", clients, per_client, p50,
              p99, all.back());
  RecordProperty("p50_ms", std::to_string(p50));
  RecordProperty("p99_ms", std::to_string(p99));
  // The scene took every drag: the server still answers and is consistent.
  auto c = r.client();
  auto scene = c.Get("/api/scene");
  ASSERT_TRUE(scene);
  EXPECT_EQ(scene->status, 200);
}

// Links in the web folder are followed only to files inside it.
TEST(ServerHttp, ServesOnlyRegularFilesInsideTheWebFolder) {
  Web web;
  fs::create_symlink(web.dir.path() / "secret.txt", web.web / "secret.txt");
  fs::create_directory_symlink(web.dir.path(), web.web / "up");
  fs::create_directory_symlink("/etc", web.web / "etc");
  fs::create_symlink(web.web / "assets/app.js", web.web / "inside.js");
  fs::create_directories(web.web / "folder");
  ServeOptions o;
  o.web_dir = web.web;
  Running r(served_character(), o);
  auto c = r.client();
  for (const char* path : {"/secret.txt", "/up/secret.txt", "/etc/passwd", "/etc/hostname", "/folder", "/folder/"}) {
    auto res = c.Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 404) << path;
    EXPECT_EQ(res->body.find("do not serve me"), std::string::npos) << path;
    EXPECT_EQ(res->body.find("root:"), std::string::npos) << path;
  }
  auto inside = c.Get("/inside.js");
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->status, 200);
  EXPECT_EQ(inside->body, "console.log('rigel');");
}

// The web app's files are compressed once per version on disk, and sent
// with an ETag that a revalidation answers with 304.
TEST(ServerHttp, StaticFilesAreCompressedOnceAndRevalidated) {
  Web web;
  std::string js;
  for (int i = 0; js.size() < 300000; ++i) js += "export const value" + std::to_string(i) + " = " + std::to_string(i * 7) + ";\n";
  write_text(web.web / "assets/app.js", js);
  ServeOptions o;
  o.web_dir = web.web;
  Running r(served_character(), o);
  auto c = r.client();
  const httplib::Headers gzip{{"Accept-Encoding", "gzip, deflate, br"}};
  std::string etag;
  for (int i = 0; i < 5; ++i) {
    auto res = c.Get("/assets/app.js", gzip);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200);
    EXPECT_EQ(res->body, js);  // the client decompressed it
    EXPECT_EQ(res->get_header_value("Content-Encoding"), "gzip");
    EXPECT_EQ(res->get_header_value("Cache-Control"), "no-cache");
    EXPECT_FALSE(res->get_header_value("ETag").empty());
    if (i == 0) etag = res->get_header_value("ETag");
    EXPECT_EQ(res->get_header_value("ETag"), etag);
  }
  EXPECT_EQ(r.http->compressions(), 1u);
  // Revalidation: the same version is a 304 without a body.
  auto same = c.Get("/assets/app.js", httplib::Headers{{"Accept-Encoding", "gzip"}, {"If-None-Match", etag}});
  ASSERT_TRUE(same);
  EXPECT_EQ(same->status, 304);
  EXPECT_TRUE(same->body.empty());
  // Without gzip: the bytes as they are, under another tag.
  auto plain = c.Get("/assets/app.js", httplib::Headers{{"Accept-Encoding", "identity"}});
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->body, js);
  EXPECT_TRUE(plain->get_header_value("Content-Encoding").empty());
  EXPECT_NE(plain->get_header_value("ETag"), etag);
  // A new version on disk: new bytes, new tag, compressed once more.
  write_text(web.web / "assets/app.js", js + "export const more = 1;\n");
  auto changed = c.Get("/assets/app.js", httplib::Headers{{"Accept-Encoding", "gzip"}, {"If-None-Match", etag}});
  ASSERT_TRUE(changed);
  EXPECT_EQ(changed->status, 200);
  EXPECT_EQ(changed->body, js + "export const more = 1;\n");
  EXPECT_NE(changed->get_header_value("ETag"), etag);
  EXPECT_EQ(r.http->compressions(), 2u);
  // HEAD: the headers, no body.
  auto head = c.Head("/index.html");
  ASSERT_TRUE(head);
  EXPECT_EQ(head->status, 200);
  EXPECT_FALSE(head->get_header_value("ETag").empty());
}

// A page of another site, or a name rebound to 127.0.0.1, must not change
// the scene: writes need Content-Type: application/json, an Origin (when
// sent) that is the server's own, and every request a Host that is this
// loopback server's. Each refusal answers JSON and changes nothing.
TEST(ServerHttp, CrossSiteWritesAreRefused) {
  Running r(served_puppet(), {});
  auto c = r.client();
  const std::string port = std::to_string(r.port);
  const std::string remove = R"({"rig": "puppet"})";
  const auto revision = [&] { return Json::parse(c.Get("/api/revision")->body)["revision"].get<std::uint64_t>(); };
  const std::uint64_t before = revision();
  struct Case {
    std::string what;
    httplib::Headers headers;
    std::string content_type;
    int status;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"text/plain", {}, "text/plain", 415, "application/json"},
      {"a form", {}, "application/x-www-form-urlencoded", 415, "application/json"},
      {"multipart", {}, "multipart/form-data; boundary=x", 415, "application/json"},
      {"json-ish", {}, "application/jsonp", 415, "application/json"},
      {"another site", {{"Origin", "http://evil.example"}}, "application/json", 403, "Origin"},
      {"another site as text", {{"Origin", "http://evil.example"}}, "text/plain", 403, "Origin"},
      {"an opaque origin", {{"Origin", "null"}}, "application/json", 403, "Origin"},
      {"another port", {{"Origin", "http://127.0.0.1:1"}}, "application/json", 403, "Origin"},
      {"https", {{"Origin", "https://127.0.0.1:" + port}}, "application/json", 403, "Origin"},
      {"rebound name", {{"Host", "evil.example:" + port}}, "application/json", 403, "Host"},
      {"rebound name, own origin", {{"Host", "evil.example:" + port}, {"Origin", "http://evil.example:" + port}},
       "application/json", 403, "Host"},
      {"another port's host", {{"Host", "127.0.0.1:1"}}, "application/json", 403, "Host"},
      {"a name with this port", {{"Host", "127.0.0.1.evil.example:" + port}}, "application/json", 403, "Host"},
      {"another loopback address", {{"Host", "127.0.0.2:" + port}}, "application/json", 403, "Host"},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.what);
    for (const char* path : {"/api/rigs/remove", "/api/save"}) {
      const std::string body = std::string(path) == "/api/save" ? R"({"path": "written.rigel"})" : remove;
      auto res = c.Post(path, k.headers, body, k.content_type.c_str());
      ASSERT_TRUE(res) << path;
      EXPECT_EQ(res->status, k.status) << path << " " << res->body;
      const Json answer = Json::parse(res->body, nullptr, false);
      ASSERT_TRUE(answer.is_object()) << res->body;
      EXPECT_NE(answer.value("error", "").find(k.says), std::string::npos) << res->body;
    }
  }
  // No Content-Type at all (the client library would add one).
  for (const char* path : {"/api/rigs/remove", "/api/save"}) {
    RawSocket raw(r.port);
    ASSERT_TRUE(raw.send(std::string("POST ") + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + port +
                         "\r\nContent-Length: " + std::to_string(remove.size()) + "\r\n\r\n" + remove));
    const std::string head = raw.answer_head();
    EXPECT_EQ(head.rfind("HTTP/1.1 415", 0), 0u) << head;
  }
  EXPECT_EQ(revision(), before);
  EXPECT_EQ(Json::parse(c.Get("/api/rigs")->body)["rigs"].size(), 1u);
  EXPECT_FALSE(fs::exists(r.served.root / "written.rigel"));
  // Reads by a rebound name are refused too (they would read the scene).
  auto read = c.Get("/api/scene", httplib::Headers{{"Host", "evil.example:" + port}});
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 403);

  // What the web app and scripts send is taken: the server's own origin by
  // any of its loopback names, a charset, no Origin at all.
  for (const httplib::Headers& ok : {httplib::Headers{{"Origin", "http://127.0.0.1:" + port}},
                                     httplib::Headers{{"Host", "localhost:" + port}, {"Origin", "http://localhost:" + port}},
                                     httplib::Headers{{"Host", "LOCALHOST:" + port}}, httplib::Headers{{"Host", "127.0.0.1"}},
                                     httplib::Headers{}}) {
    auto res = c.Post("/api/select", ok, R"({"controls": ["hand.L"]})", "application/json; charset=utf-8");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200) << res->body;
  }
  // HTTP/1.0 without a Host header (scripts/demo's probe).
  RawSocket raw(r.port);
  ASSERT_TRUE(raw.send("GET /api/revision HTTP/1.0\r\n\r\n"));
  EXPECT_EQ(raw.answer_head().rfind("HTTP/1.1 200", 0), 0u);
  auto gone = c.Post("/api/rigs/remove", httplib::Headers{{"Origin", "http://127.0.0.1:" + port}}, remove, "application/json");
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->status, 200) << gone->body;
}

// Off loopback a token is required, and any Host is taken (the machine's
// names are not known), but an Origin must still be the Host's.
TEST(ServerHttp, OffLoopbackWritesNeedTheTokenAndTheirOwnOrigin) {
  {
    Served s = served_character();
    ServeOptions o;
    o.host = "0.0.0.0";
    o.port = 0;
    HttpServer http(*s.workspace, o);
    auto bound = http.bind();
    ASSERT_FALSE(bound.is_ok());
    EXPECT_NE(bound.status().message().find("token"), std::string::npos) << bound.status().message();
  }
  ServeOptions o;
  o.host = "0.0.0.0";
  o.token = "s3cret";
  Running r(served_puppet(), o);
  auto c = r.client();
  const std::string port = std::to_string(r.port);
  const char* body = R"({"controls": ["hand.L"]})";
  EXPECT_EQ(c.Post("/api/select", body, "application/json")->status, 401);
  const httplib::Headers token{{"Authorization", "Bearer s3cret"}, {"Host", "studio-7.local:" + port}};
  EXPECT_EQ(c.Post("/api/select", token, body, "application/json")->status, 200);
  httplib::Headers cross = token;
  cross.emplace("Origin", "http://evil.example");
  EXPECT_EQ(c.Post("/api/select", cross, body, "application/json")->status, 403);
  httplib::Headers own = token;
  own.emplace("Origin", "http://studio-7.local:" + port);
  EXPECT_EQ(c.Post("/api/select", own, body, "application/json")->status, 200);
  EXPECT_EQ(c.Post("/api/select", token, body, "text/plain")->status, 415);
}

// Connections that send nothing hold no one up: a request made while many
// are open is answered while they are still open.
TEST(ServerHttp, IdleConnectionsDoNotBlockOthers) {
  Running r(served_puppet(), {});
  std::vector<std::unique_ptr<RawSocket>> idle;
  for (int i = 0; i < 64; ++i) {
    idle.push_back(std::make_unique<RawSocket>(r.port));
    ASSERT_GE(idle.back()->fd, 0) << i;
  }
  // A half-sent request too.
  ASSERT_TRUE(idle.front()->send("POST /api/select HTTP/1.1\r\nContent-Length: 100\r\n\r\n{"));
  httplib::Client c("127.0.0.1", r.port);
  c.set_read_timeout(120, 0);
  auto res = c.Get("/api/revision");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  int still_open = 0;
  for (const auto& s : idle) still_open += s->open();
  EXPECT_EQ(still_open, 64) << "the answer came only once the server had dropped idle connections";
}

// Framing the server cannot read right is answered 400 (413 over the body
// limit) at once, without waiting for a body, and the connection closed.
TEST(ServerHttp, MalformedFramingIsAnswered400AtOnce) {
  Running r(served_puppet(), {});
  struct Case {
    std::string headers;
    std::string status;
  };
  const std::vector<Case> cases = {
      {"Content-Length: -1\r\n", "400"},
      {"Content-Length: abc\r\n", "400"},
      {"Content-Length: 5, 5\r\n", "400"},
      {"Content-Length: 3\r\nContent-Length: 4\r\n", "400"},
      {"Content-Length: 99999999999999999999999999\r\n", "413"},
      {"Content-Length: 5000000000\r\n", "413"},
      {"Transfer-Encoding: gzip\r\n", "400"},
      {"Transfer-Encoding: chunked\r\nContent-Length: 3\r\n", "400"},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.headers);
    RawSocket raw(r.port);
    ASSERT_TRUE(raw.send("POST /api/select HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(r.port) +
                         "\r\nContent-Type: application/json\r\n" + k.headers + "\r\n{}"));
    const std::string head = raw.answer_head();
    EXPECT_EQ(head.rfind("HTTP/1.1 " + k.status, 0), 0u) << head;
    EXPECT_NE(lower_copy(head).find("connection: close"), std::string::npos) << head;
  }
  auto c = r.client();
  auto ok = c.Post("/api/select", R"({"controls": ["hand.L"]})", "application/json");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200);
}

}  // namespace
}  // namespace rigel::server
