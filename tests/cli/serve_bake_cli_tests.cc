// `rigel serve` (starts, answers on loopback, stops cleanly on SIGTERM,
// refuses bad arguments) and `rigel bake` from the command line.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;

const std::string kCharacter = std::string(RIGEL_SOURCE_DIR) + "/tests/data/gltf/rigify_human_metarig.glb";

// One HTTP/1.0 GET on 127.0.0.1:port; the whole answer ("" when refused).
std::string http_get(int port, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return "";
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string answer;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    const std::string request = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
    if (::send(fd, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size())) {
      char buffer[4096];
      for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) answer.append(buffer, static_cast<std::size_t>(n));
    }
  }
  ::close(fd);
  return answer;
}

TEST(CliServe, ServesTheBundledRigAndStopsOnSigterm) {
  TempDir dir;
  fs::create_directories(dir.path() / "web");
  std::ofstream(dir.path() / "web/index.html") << "<!doctype html><title>rigel test</title>";
  const std::string port_file = (dir.path() / "port").string();
  const std::string out = (dir.path() / "out").string(), err = (dir.path() / "err").string();
  std::vector<std::string> words = {RIGEL_CLI_PATH, "serve", kCharacter, "--rig",
                                    std::string(RIGEL_SOURCE_DIR) + "/examples/puppet.rig.xml", "--port", "0",
                                    "--port-file", port_file, "--root", dir.path().string(), "--web",
                                    (dir.path() / "web").string()};
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, RIGEL_CLI_PATH, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);

  int port = 0;
  for (int i = 0; i < 600 && port == 0; ++i) {  // up to a minute (sanitizer builds are slow)
    std::ifstream in(port_file);
    if (!(in >> port)) {
      port = 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  ASSERT_GT(port, 0) << read_text(err);
  const std::string scene = http_get(port, "/api/scene");
  EXPECT_TRUE(contains(scene, "200 OK")) << scene;
  EXPECT_TRUE(contains(scene, "\"mode\":\"forward\"")) << scene;
  const std::string rigs = http_get(port, "/api/rigs");
  EXPECT_TRUE(contains(rigs, "\"name\":\"puppet\"")) << rigs;
  EXPECT_TRUE(contains(http_get(port, "/"), "<title>rigel test</title>"));
  EXPECT_TRUE(contains(http_get(port, "/../port"), "404") || contains(http_get(port, "/../port"), "400"));

  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  EXPECT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << read_text(err);
  EXPECT_TRUE(contains(read_text(out), "http://127.0.0.1:" + std::to_string(port) + "/")) << read_text(out);
  EXPECT_TRUE(contains(read_text(err), "server stopped")) << read_text(err);
}

// Off loopback the server needs a token for writes: serve makes one when
// none is given and prints it (the URL carries it for the web app).
TEST(CliServe, OffLoopbackMakesAToken) {
  TempDir dir;
  const std::string out = (dir.path() / "out").string(), err = (dir.path() / "err").string();
  std::vector<std::string> words = {RIGEL_CLI_PATH, "serve", "--host", "0.0.0.0", "--port", "0", "--json",
                                    "--root", dir.path().string()};
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, RIGEL_CLI_PATH, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  nlohmann::json printed;
  for (int i = 0; i < 600 && !printed.is_object(); ++i) {  // up to a minute (sanitizer builds are slow)
    printed = nlohmann::json::parse(read_text(out), nullptr, false);
    if (!printed.is_object()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(printed.is_object()) << read_text(err);
  const std::string token = printed.value("token", "");
  EXPECT_EQ(token.size(), 32u) << printed;
  EXPECT_TRUE(contains(printed.value("url", ""), "?token=" + token)) << printed;
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_text(err);
}

TEST(CliServe, RefusesBadArguments) {
  TempDir dir;
  EXPECT_TRUE(exited_with(rigel({"serve", "--port", "70000"}), 2));
  const CliRun root = rigel({"serve", "--root", (dir.path() / "nowhere").string(), "--port", "0"});
  EXPECT_TRUE(exited_with(root, 2)) << root;
  EXPECT_TRUE(contains(root.err, "not a folder")) << root;
  const CliRun missing = rigel({"serve", (dir.path() / "missing.rigel").string(), "--port", "0"});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
  const CliRun web = rigel({"serve", "--web", dir.path().string(), "--port", "0"});
  EXPECT_TRUE(exited_with(web, 1)) << web;
  EXPECT_TRUE(contains(web.err, "index.html")) << web;
}

TEST(CliBake, BakesTheRigIntoJointKeys) {
  TempDir dir;
  const std::string def = (dir.path() / "arm.rig.json").string();
  std::ofstream(def) << R"({"rig": {"name": "arm", "version": "1.0", "components": [{
      "type": "fkChain", "name": "arm", "side": "L", "version": "1.0",
      "rigId": "7c2d4b9e-3f1a-4e6b-8d0c-5a9b2e1f3c02",
      "guides": [{"joint": "upper_arm.L"}, {"joint": "forearm.L"}, {"joint": "hand.L"}]}]}})";
  const std::string built = (dir.path() / "arm.rigel").string(), baked = (dir.path() / "baked.rigel").string();
  ASSERT_TRUE(exited_with(rigel({"build", def, "--character", kCharacter, "-o", built}), 0));
  const CliRun run = rigel({"bake", built, "--frames", "0:4", "--nodes", "upper_arm.L,forearm.L,hand.L", "-o", baked, "--json"});
  ASSERT_TRUE(exited_with(run, 0)) << run;
  const auto report = nlohmann::ordered_json::parse(run.out);
  EXPECT_EQ(report["nodes"], 3);
  EXPECT_EQ(report["frames"], 5);
  EXPECT_EQ(report["keys"], 3 * 5 * 4);
  EXPECT_EQ(report["disconnected"], 9);  // translate, rotate, scale of each joint from its drive node
  // The baked joints are driven by curves now: removing the rig keeps the pose.
  const std::string removed = (dir.path() / "removed.rigel").string();
  ASSERT_TRUE(exited_with(rigel({"remove", baked, "--rig", "arm", "-o", removed, "--json"}), 0));
  const CliRun inspect = rigel({"inspect", removed, "--json"});
  EXPECT_TRUE(contains(inspect.out, "forearm.L_rotateX")) << inspect;

  EXPECT_TRUE(exited_with(rigel({"bake", built, "--frames", "4", "-o", baked}), 2));
  const CliRun reversed = rigel({"bake", built, "--frames", "4:0", "-o", baked});
  EXPECT_TRUE(exited_with(reversed, 1)) << reversed;
  EXPECT_TRUE(contains(reversed.err, "first <= last")) << reversed;
  const CliRun nobody = rigel({"bake", built, "--frames", "0:4", "--nodes", "nobody", "-o", baked});
  EXPECT_TRUE(exited_with(nobody, 1)) << nobody;
  EXPECT_TRUE(contains(nobody.err, "no node 'nobody'")) << nobody;
}

}  // namespace
}  // namespace rigel::cli::testing
