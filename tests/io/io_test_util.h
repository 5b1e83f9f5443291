#pragma once
// Helpers shared by the io tests: fixture paths, files and temporary
// folders, building scenes with checked calls, and an exact comparison of
// two graphs (what "load(save(s)) is s" means).

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/scene/scene.h"

namespace rigel::io::testing {

namespace fs = std::filesystem;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Uuid;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
using scene::Scene;

// RIGEL_SOURCE_DIR is the project root, set by tests/io/CMakeLists.txt.
inline fs::path source_dir() { return fs::path(RIGEL_SOURCE_DIR); }
inline fs::path scenes_dir() { return source_dir() / "tests" / "data" / "scenes"; }
inline fs::path example_path() { return source_dir() / "examples" / "cmu_131_skeleton.rigel"; }

inline std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "the test should be able to read " << path;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// The Khronos glTF-Validator (tools/validate-gltf.mjs, npm gltf-validator
// installed by `npm ci` in web/) on one file: "" when it finds no error, its
// report of the errors otherwise, and nullopt when node or the package is
// not installed (the caller says so and skips; it never passes silently).
inline std::optional<std::string> gltf_validator_errors(const fs::path& path) {
  const fs::path script = source_dir() / "tools" / "validate-gltf.mjs";
  auto quoted = [](const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
  };
  const std::string command = "node " + quoted(script.string()) + " " + quoted(path.string()) + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return std::nullopt;
  std::string output;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  const int status = ::pclose(pipe);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 0) return std::string();
  if (code == 3 || code == 127) return std::nullopt;  // the package, or node itself, is missing
  return output.empty() ? std::string("the validator failed (exit ") + std::to_string(code) + ")" : output;
}

// Fails the test when the validator finds an error in `path`; when the
// validator is not installed, says so once per process and checks nothing.
#define EXPECT_VALID_GLTF(path)                                                                               \
  do {                                                                                                        \
    const std::optional<std::string> errors_ = ::rigel::io::testing::gltf_validator_errors(path);             \
    if (!errors_) {                                                                                           \
      static bool said_ = false;                                                                              \
      if (!said_) std::cerr << "note: the glTF validator is not installed (npm ci in web/); not validated\n"; \
      said_ = true;                                                                                           \
    } else {                                                                                                  \
      EXPECT_EQ(*errors_, "") << "the Khronos glTF-Validator finds errors in " << (path);                     \
    }                                                                                                         \
  } while (0)

inline void write_text(const fs::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  EXPECT_TRUE(out.good()) << "the test should be able to write " << path;
}

// A fresh folder under the system temporary folder, removed on destruction.
// Unique per process and per instance, so tests may run in parallel.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("rigel_io_tests_" + std::to_string(::getpid()) + "_" + std::to_string(counter.fetch_add(1)));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  // Names of the entries in the folder, sorted.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

// A deterministic UUID for fixtures: a1b2c3d4-0000-4000-8000-<index, 12 digits>.
inline Uuid fixed_uuid(int index) {
  char text[40];
  std::snprintf(text, sizeof text, "a1b2c3d4-0000-4000-8000-%012d", index);
  return *Uuid::parse(text);
}

// Scene building with every call checked: a refused call fails the test
// with the library's reason.
class Builder {
 public:
  explicit Builder(Scene& scene) : scene_(scene), graph_(scene.graph()) {}

  NodeId node(std::string_view type, std::string_view name, int uuid_index, NodeId parent = NodeId{}) {
    Result<NodeId> id = graph_.create_node(type, name, fixed_uuid(uuid_index));
    EXPECT_TRUE(id.is_ok()) << "creating " << type << " '" << name << "' should succeed: " << id.status().message();
    if (!id.is_ok()) return NodeId{};
    EXPECT_EQ(graph_.node(*id)->name(), name) << "the fixture's names are unique, so none should get a suffix";
    if (parent.is_valid()) {
      Status s = graph_.set_parent(*id, parent);
      EXPECT_TRUE(s.is_ok()) << "parenting '" << name << "' should succeed: " << s.message();
    }
    return *id;
  }

  void set(NodeId node, std::string_view attr, Value value, std::int32_t element = -1) {
    Result<Plug> plug = graph_.plug_find(node, attr, element);
    ASSERT_TRUE(plug.is_ok()) << "plug " << attr << " should exist: " << plug.status().message();
    Status s = graph_.set_value(*plug, std::move(value));
    EXPECT_TRUE(s.is_ok()) << "setting " << graph_.plug_name(*plug) << " should succeed: " << s.message();
  }

  void connect(std::string_view src, std::string_view dst) {
    Result<Plug> s = graph_.plug_find(src);
    Result<Plug> d = graph_.plug_find(dst);
    ASSERT_TRUE(s.is_ok() && d.is_ok()) << "plugs " << src << " and " << dst << " should exist";
    Status c = graph_.connect(*s, *d);
    EXPECT_TRUE(c.is_ok()) << "connecting " << src << " -> " << dst << " should succeed: " << c.message();
  }

  void tag(NodeId node, const std::string& key, const std::string& value) {
    Status s = graph_.set_tag(node, key, value);
    EXPECT_TRUE(s.is_ok()) << "tagging should succeed: " << s.message();
  }

 private:
  Scene& scene_;
  Graph& graph_;
};

inline std::string plug_identity(const Graph& g, const Plug& p) {
  const graph::Node* n = g.node(p.node);
  std::string text = n ? n->uuid().str() + "." + n->type().attr(p.attr).name : "<stale>";
  // append, not "[" + ...: GCC 12 warns falsely (-Wrestrict) on that form here.
  if (p.element >= 0) text.append("[").append(std::to_string(p.element)).append("]");
  return text;
}

// Exact equality of two graphs after evaluating both: frame rate and time;
// nodes in the same order with the same uuid, name, type, tags and every
// attribute value bit for bit (graph::values_identical); the same
// connections (by uuid, attribute and element).
inline ::testing::AssertionResult graphs_identical(Graph& a, Graph& b) {
  a.evaluate_all(graph::Execution::kSerial);
  b.evaluate_all(graph::Execution::kSerial);
  if (std::bit_cast<std::uint64_t>(a.fps()) != std::bit_cast<std::uint64_t>(b.fps()) ||
      std::bit_cast<std::uint64_t>(a.time()) != std::bit_cast<std::uint64_t>(b.time()))
    return ::testing::AssertionFailure() << "fps/time differ: " << a.fps() << "/" << a.time() << " vs " << b.fps()
                                         << "/" << b.time();
  std::vector<NodeId> na = a.nodes(), nb = b.nodes();
  if (na.size() != nb.size())
    return ::testing::AssertionFailure() << "node counts differ: " << na.size() << " vs " << nb.size();
  for (std::size_t i = 0; i < na.size(); ++i) {
    const graph::Node& x = *a.node(na[i]);
    const graph::Node& y = *b.node(nb[i]);
    const std::string where = "node " + std::to_string(i) + " ('" + x.name() + "')";
    if (x.uuid() != y.uuid())
      return ::testing::AssertionFailure() << where << ": uuid " << x.uuid().str() << " vs " << y.uuid().str();
    if (x.name() != y.name()) return ::testing::AssertionFailure() << where << ": name vs '" << y.name() << "'";
    if (x.type().name() != y.type().name() || x.type().attr_count() != y.type().attr_count())
      return ::testing::AssertionFailure() << where << ": type " << x.type().name() << " vs " << y.type().name();
    if (x.tags() != y.tags()) return ::testing::AssertionFailure() << where << ": tags differ";
    for (graph::AttrIndex k = 0; k < x.type().attr_count(); ++k) {
      if (!graph::values_identical(x.value(k), y.value(k)))
        return ::testing::AssertionFailure() << where << "." << x.type().attr(k).name << ": "
                                             << graph::value_to_text(x.value(k)) << " vs "
                                             << graph::value_to_text(y.value(k));
    }
  }
  std::vector<graph::Connection> ca = a.connections(), cb = b.connections();
  if (ca.size() != cb.size())
    return ::testing::AssertionFailure() << "connection counts differ: " << ca.size() << " vs " << cb.size();
  for (std::size_t i = 0; i < ca.size(); ++i) {
    std::string x = plug_identity(a, ca[i].src) + " -> " + plug_identity(a, ca[i].dst);
    std::string y = plug_identity(b, cb[i].src) + " -> " + plug_identity(b, cb[i].dst);
    if (x != y) return ::testing::AssertionFailure() << "connection " << i << ": " << x << " vs " << y;
  }
  return ::testing::AssertionSuccess();
}

// Where two texts first differ, as "line N: <a> | <b>" (for failure
// messages that stay short when the texts are long).
inline std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  for (int line = 1;; ++line) {
    bool ga = static_cast<bool>(std::getline(sa, la));
    bool gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga && !gb) return "texts are identical";
    if (!ga || !gb || la != lb)
      return "line " + std::to_string(line) + ": <" + (ga ? la : "(end)") + "> vs <" + (gb ? lb : "(end)") + ">";
  }
}

}  // namespace rigel::io::testing
