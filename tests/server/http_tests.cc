// `rigel serve` over real sockets on loopback: static files without path
// traversal, tokens, body limits, errors that leave the server serving, and
// a bounded load test of concurrent drags (p99 latency reported).

#include <gtest/gtest.h>

#include <algorithm>
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

}  // namespace
}  // namespace rigel::server
