#include "rigel/io/scene_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <ostream>
#include <streambuf>
#include <mutex>
#include <set>
#include <sstream>
#include <unordered_map>
#include <variant>

#include <nlohmann/json.hpp>

#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/ops/registry.h"

namespace rigel::io {
namespace {

using Json = nlohmann::ordered_json;
using graph::AttrIndex;
using graph::AttrSpec;
using graph::AttrType;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using graph::ValueType;
using math::Mat4;
using math::Quat;
using math::Vec3;

// ---- file paths ------------------------------------------------------------

struct PathAttributes {
  std::mutex mutex;
  std::set<std::pair<std::string, std::string>, std::less<>> declared;
};
PathAttributes& path_attributes() {
  static PathAttributes p;
  return p;
}

// Rewrites the declared path attributes of every node of a scene's JSON.
template <typename F>
void rewrite_paths(Json& root, F&& rewrite) {
  if (!root.is_object() || !root.contains("nodes") || !root["nodes"].is_array()) return;
  for (Json& n : root["nodes"]) {
    if (!n.is_object() || !n.contains("type") || !n["type"].is_string() || !n.contains("attrs") || !n["attrs"].is_object())
      continue;
    const std::string type = n["type"].get<std::string>();
    for (auto it = n["attrs"].begin(); it != n["attrs"].end(); ++it)
      if (it.value().is_string() && !it.value().get_ref<const std::string&>().empty() && is_path_attribute(type, it.key()))
        it.value() = rewrite(it.value().get<std::string>());
  }
}

// ---- encoding --------------------------------------------------------------

Json encode_double(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

Json encode_doubles(const double* d, int n) {
  Json a = Json::array();
  for (int i = 0; i < n; ++i) a.push_back(encode_double(d[i]));
  return a;
}

Json encode_scalar(const Value& v, const AttrSpec& spec) {
  return std::visit(
      [&](const auto& x) -> Json {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string>) {
          return x;
        } else if constexpr (std::is_same_v<T, std::int64_t>) {
          if (spec.type.value == ValueType::kEnum && x >= 0 && x < static_cast<std::int64_t>(spec.enum_names.size()))
            return spec.enum_names[static_cast<std::size_t>(x)];
          return x;
        } else if constexpr (std::is_same_v<T, double>) {
          return encode_double(x);
        } else if constexpr (std::is_same_v<T, Vec3>) {
          return encode_doubles(x.data(), 3);
        } else if constexpr (std::is_same_v<T, Quat>) {
          return encode_doubles(x.coeffs().data(), 4);
        } else if constexpr (std::is_same_v<T, Mat4>) {
          return encode_doubles(x.data(), 16);  // Eigen is column-major, as glTF
        } else {
          return nullptr;
        }
      },
      v);
}

Json encode_value(const Value& v, const AttrSpec& spec) {
  if (!spec.type.array) return encode_scalar(v, spec);
  Json a = Json::array();
  for (std::size_t i = 0; i < graph::array_size(v); ++i) a.push_back(encode_scalar(graph::array_element(v, spec.type, i), spec));
  return a;
}

bool is_hierarchy(const Graph& g, const graph::Connection& c) {
  const graph::NodeType& s = g.node(c.src.node)->type();
  const graph::NodeType& d = g.node(c.dst.node)->type();
  return c.src.element < 0 && c.dst.element < 0 && c.src.component < 0 && c.dst.component < 0 &&
         c.src.attr == s.world_output() && c.dst.attr == d.parent_input();
}

// ---- decoding --------------------------------------------------------------

Result<double> decode_double(const Json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const auto& s = j.get_ref<const std::string&>();
    if (s == "nan") return std::nan("");
    if (s == "inf") return HUGE_VAL;
    if (s == "-inf") return -HUGE_VAL;
  }
  return error(ErrorCode::kParseError, "expected a number, got " + j.dump());
}

Status decode_doubles(const Json& j, double* out, int n) {
  if (!j.is_array() || j.size() != static_cast<std::size_t>(n))
    return error(ErrorCode::kParseError, "expected an array of " + std::to_string(n) + " numbers, got " +
                                             (j.is_array() ? std::to_string(j.size()) + " elements" : j.dump()));
  for (int i = 0; i < n; ++i) {
    Result<double> d = decode_double(j[static_cast<std::size_t>(i)]);
    if (!d) return d.status().with_context("[" + std::to_string(i) + "]");
    out[i] = *d;
  }
  return Status::ok();
}

Result<Value> decode_scalar(const Json& j, const AttrSpec& spec) {
  switch (spec.type.value) {
    case ValueType::kMessage:
      return error(ErrorCode::kParseError, "message attributes hold no value");
    case ValueType::kBool:
      if (!j.is_boolean()) return error(ErrorCode::kParseError, "expected true or false, got " + j.dump());
      return Value(j.get<bool>());
    case ValueType::kInt:
      if (!j.is_number_integer()) return error(ErrorCode::kParseError, "expected an integer, got " + j.dump());
      return Value(j.get<std::int64_t>());
    case ValueType::kEnum: {
      if (j.is_number_integer()) {
        auto v = j.get<std::int64_t>();
        if (v >= 0 && v < static_cast<std::int64_t>(spec.enum_names.size())) return Value(v);
      } else if (j.is_string()) {
        for (std::size_t i = 0; i < spec.enum_names.size(); ++i)
          if (spec.enum_names[i] == j.get_ref<const std::string&>()) return Value(static_cast<std::int64_t>(i));
      }
      std::string names;
      for (const auto& n : spec.enum_names) names += (names.empty() ? "" : ", ") + n;
      return error(ErrorCode::kParseError, "expected one of " + names + ", got " + j.dump());
    }
    case ValueType::kDouble: {
      Result<double> d = decode_double(j);
      if (!d) return d.status();
      return Value(*d);
    }
    case ValueType::kDouble3: {
      Vec3 v;
      if (Status s = decode_doubles(j, v.data(), 3); !s) return s;
      return Value(v);
    }
    case ValueType::kQuat: {
      Quat q;
      if (Status s = decode_doubles(j, q.coeffs().data(), 4); !s) return s;
      return Value(q);
    }
    case ValueType::kMatrix: {
      Mat4 m;
      if (Status s = decode_doubles(j, m.data(), 16); !s) return s;
      return Value(m);
    }
    case ValueType::kString:
      if (!j.is_string()) return error(ErrorCode::kParseError, "expected a string, got " + j.dump());
      return Value(j.get<std::string>());
  }
  return error(ErrorCode::kParseError, "unknown type");
}

Result<Value> decode_value(const Json& j, const AttrSpec& spec) {
  if (!spec.type.array) return decode_scalar(j, spec);
  if (!j.is_array()) return error(ErrorCode::kParseError, "expected an array of " + graph::type_name({spec.type.value, false}) + ", got " + j.dump());
  Value array = graph::zero_value(spec.type);
  for (std::size_t i = 0; i < j.size(); ++i) {
    Result<Value> e = decode_scalar(j[i], spec);
    if (!e) return e.status().with_context("[" + std::to_string(i) + "]");
    graph::array_set_element(array, spec.type, i, *e);
  }
  return array;
}

Status check_keys(const Json& object, std::initializer_list<const char*> allowed) {
  for (auto it = object.begin(); it != object.end(); ++it) {
    bool known = false;
    for (const char* a : allowed) known |= it.key() == a;
    if (!known) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      return error(ErrorCode::kParseError, "unknown key '" + it.key() + "' (expected " + list + ")");
    }
  }
  return Status::ok();
}

class Loader {
 public:
  Loader(const std::string& source, std::shared_ptr<const graph::Registry> registry)
      : source_(source), registry_(registry ? std::move(registry) : ops::default_registry()) {}

  Result<std::unique_ptr<scene::Scene>> load(const Json& root) {
    auto scene = std::make_unique<scene::Scene>(registry_);
    Graph& g = scene->graph();
    if (!root.is_object()) return fail("", "a scene file is a JSON object");
    if (Status s = check_keys(root, {"rigel", "version", "fps", "time", "nodes", "connections"}); !s) return fail("", s);
    if (!root.contains("rigel") || root["rigel"] != "scene") return fail("rigel", "not a rigel scene file (expected \"rigel\": \"scene\")");
    if (!root.contains("version") || !root["version"].is_number_integer()) return fail("version", "missing or not an integer");
    const auto version = root["version"].get<std::int64_t>();
    if (version < 1 || version > kSceneFormatVersion)
      return error(ErrorCode::kUnsupported, source_ + ": version " + std::to_string(version) +
                                                " is not supported (this build reads versions 1 to " +
                                                std::to_string(kSceneFormatVersion) + ")");
    if (root.contains("fps")) {
      if (!root["fps"].is_number()) return fail("fps", "expected a number");
      if (Status s = g.set_fps(root["fps"].get<double>()); !s) return fail("fps", s);
    }
    if (root.contains("time")) {
      if (!root["time"].is_number() || !std::isfinite(root["time"].get<double>())) return fail("time", "expected a finite number of seconds");
      g.set_time(root["time"].get<double>());
    }
    const Json empty = Json::array();
    const Json& nodes = root.contains("nodes") ? root["nodes"] : empty;
    if (!nodes.is_array()) return fail("nodes", "expected an array");

    // Pass 1: create every node, so parents and connections can refer forward.
    std::vector<NodeId> ids;
    std::unordered_map<std::string, std::size_t> index_of;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const Json& n = nodes[i];
      const std::string where = "nodes[" + std::to_string(i) + "]";
      if (!n.is_object()) return fail(where, "expected an object");
      if (Status s = check_keys(n, {"name", "type", "uuid", "parent", "attrs", "tags"}); !s) return fail(where, s);
      if (!n.contains("name") || !n["name"].is_string()) return fail(where + ".name", "missing or not a string");
      if (!n.contains("type") || !n["type"].is_string()) return fail(where + ".type", "missing or not a string");
      const std::string name = n["name"].get<std::string>();
      const std::string named = where + " (" + name + ")";
      if (auto it = index_of.find(name); it != index_of.end())
        return fail(named + ".name", "duplicate node name (also nodes[" + std::to_string(it->second) + "])");
      graph::Uuid uuid;
      if (n.contains("uuid")) {
        std::optional<graph::Uuid> parsed = n["uuid"].is_string() ? graph::Uuid::parse(n["uuid"].get<std::string>()) : std::nullopt;
        if (!parsed || parsed->is_nil()) return fail(named + ".uuid", "not a UUID: " + n["uuid"].dump());
        if (g.find(*parsed).is_valid()) return fail(named + ".uuid", "duplicate uuid " + parsed->str());
        uuid = *parsed;
      }
      if (!Graph::is_valid_name(name)) return fail(named + ".name", "invalid node name (printable, no spaces or brackets)");
      Result<NodeId> id = g.create_node(n["type"].get<std::string>(), name, uuid);
      if (!id) return fail(named + ".type", id.status());
      ids.push_back(*id);
      index_of.emplace(name, i);
    }
    // Pass 2: attributes, tags, parents.
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const Json& n = nodes[i];
      const std::string named = "nodes[" + std::to_string(i) + "] (" + n["name"].get<std::string>() + ")";
      const graph::NodeType& type = g.node(ids[i])->type();
      if (n.contains("attrs")) {
        const Json& attrs = n["attrs"];
        if (!attrs.is_object()) return fail(named + ".attrs", "expected an object");
        for (auto it = attrs.begin(); it != attrs.end(); ++it) {
          const std::string where = named + ".attrs." + it.key();
          AttrIndex a = type.attr_find(it.key());
          if (a == graph::kNoAttr) return fail(where, "node type '" + type.name() + "' has no attribute '" + it.key() + "'");
          const AttrSpec& spec = type.attr(a);
          if (!(spec.flags & graph::kInput) || !(spec.flags & graph::kStorable)) return fail(where, "this attribute is not stored in files");
          Result<Value> v = decode_value(it.value(), spec);
          if (!v) return fail(where, v.status());
          if (Status s = g.set_value(Plug{ids[i], a, -1}, std::move(*v)); !s) return fail(where, s);
        }
      }
      if (n.contains("tags")) {
        const Json& tags = n["tags"];
        if (!tags.is_object()) return fail(named + ".tags", "expected an object of strings");
        for (auto it = tags.begin(); it != tags.end(); ++it) {
          if (!it.value().is_string()) return fail(named + ".tags." + it.key(), "expected a string");
          if (Status s = g.set_tag(ids[i], it.key(), it.value().get<std::string>()); !s) return fail(named + ".tags", s);
        }
      }
      if (n.contains("parent")) {
        if (!n["parent"].is_string()) return fail(named + ".parent", "expected a node name");
        NodeId parent = g.find(n["parent"].get<std::string>());
        if (!parent.is_valid()) return fail(named + ".parent", "no node named '" + n["parent"].get<std::string>() + "'");
        if (Status s = g.set_parent(ids[i], parent); !s) return fail(named + ".parent", s);
      }
    }
    // Pass 3: connections.
    if (root.contains("connections")) {
      const Json& connections = root["connections"];
      if (!connections.is_array()) return fail("connections", "expected an array");
      for (std::size_t i = 0; i < connections.size(); ++i) {
        const Json& c = connections[i];
        const std::string where = "connections[" + std::to_string(i) + "]";
        if (!c.is_object()) return fail(where, "expected an object with src and dst");
        if (Status s = check_keys(c, {"src", "dst"}); !s) return fail(where, s);
        Plug ends[2];
        const char* keys[2] = {"src", "dst"};
        for (int k = 0; k < 2; ++k) {
          if (!c.contains(keys[k]) || !c[keys[k]].is_string()) return fail(where + "." + keys[k], "missing or not a string");
          Result<Plug> p = g.plug_find(c[keys[k]].get<std::string>());
          if (!p) return fail(where + "." + keys[k], p.status());
          ends[k] = *p;
        }
        if (Status s = g.connect(ends[0], ends[1]); !s) return fail(where, s);
      }
    }
    g.clear_history();
    return scene;
  }

 private:
  Status fail(const std::string& where, const std::string& message) const {
    return error(ErrorCode::kParseError, source_ + (where.empty() ? "" : ": " + where) + ": " + message);
  }
  Status fail(const std::string& where, const Status& status) const {
    return Status(status.code() == ErrorCode::kOk ? ErrorCode::kParseError : status.code(),
                  source_ + (where.empty() ? "" : ": " + where) + ": " + status.message());
  }

  std::string source_;
  std::shared_ptr<const graph::Registry> registry_;
};

// Accepts everything and remembers where a parse stopped. nlohmann reports
// some failures without a position (a number beyond the range of a double
// throws out_of_range, not parse_error); a second pass with this finds it.
class ErrorLocator : public nlohmann::json_sax<Json> {
 public:
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t position, const std::string&, const Json::exception&) override {
    byte = position;
    return false;
  }
  std::size_t byte = 0;
};

}  // namespace

void declare_path_attribute(std::string_view node_type, std::string_view attr) {
  PathAttributes& p = path_attributes();
  std::lock_guard lock(p.mutex);
  p.declared.emplace(std::string(node_type), std::string(attr));
}

bool is_path_attribute(std::string_view node_type, std::string_view attr) {
  PathAttributes& p = path_attributes();
  std::lock_guard lock(p.mutex);
  return p.declared.count(std::pair<std::string, std::string>(node_type, attr)) > 0;
}

std::string path_relative_to(const std::string& path, const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) return path;
  const fs::path base = fs::weakly_canonical(fs::absolute(folder.empty() ? fs::path(".") : folder, ec), ec);
  if (ec) return target.string();
  const fs::path relative = target.lexically_relative(base);
  return relative.empty() ? target.string() : relative.generic_string();
}

std::string path_from(const std::string& stored, const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path p(stored);
  if (p.is_relative()) p = fs::absolute(folder.empty() ? fs::path(".") : folder, ec) / p;
  const fs::path resolved = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal().string() : resolved.string();
}

nlohmann::ordered_json attribute_to_json(const graph::Value& value, const graph::AttrSpec& spec) {
  return encode_value(value, spec);
}

Result<graph::Value> attribute_from_json(const nlohmann::ordered_json& json, const graph::AttrSpec& spec) {
  return decode_value(json, spec);
}

namespace {

// Scene files nest a few levels (a matrix array in an attribute of a node);
// deeper text is refused before it is parsed, at the bracket that passes
// the limit (strings skipped; the text need not be valid JSON).
constexpr std::size_t kMaxSceneDepth = 256;

Result<std::unique_ptr<scene::Scene>> parse_scene_in(std::string_view text, const std::string& source,
                                                     std::shared_ptr<const graph::Registry> registry,
                                                     const std::filesystem::path* folder) {
  if (const std::size_t deep = json_too_deep(text, kMaxSceneDepth); deep != std::string_view::npos)
    return error(ErrorCode::kParseError, source + ":" + line_column(text, deep) +
                                             ": arrays and objects nest deeper than " +
                                             std::to_string(kMaxSceneDepth) + " levels (the limit)");
  Json root;
  try {
    root = Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& e) {
    std::string what = e.what();
    // Drop nlohmann's "[json.exception.parse_error.101] parse error at line 1, column 2: " prefix;
    // we say where ourselves.
    if (auto colon = what.find(": "); colon != std::string::npos && what.find("parse error") != std::string::npos)
      what = what.substr(colon + 2);
    return error(ErrorCode::kParseError, source + ":" + line_column(text, e.byte == 0 ? 0 : e.byte - 1) + ": " + what);
  } catch (const Json::exception& e) {
    // Any other nlohmann error (out_of_range.406: "number overflow parsing
    // '1e999'") would otherwise escape to the caller and end the process.
    std::string what = e.what();
    if (auto bracket = what.find("] "); bracket != std::string::npos) what = what.substr(bracket + 2);
    ErrorLocator locator;
    (void)Json::sax_parse(text.begin(), text.end(), &locator);
    return error(ErrorCode::kParseError,
                 source + ":" + line_column(text, locator.byte == 0 ? 0 : locator.byte - 1) + ": " + what);
  }
  if (folder) rewrite_paths(root, [&](const std::string& p) { return path_from(p, *folder); });
  return Loader(source, std::move(registry)).load(root);
}
}  // namespace

Result<std::unique_ptr<scene::Scene>> parse_scene(std::string_view text, const std::string& source,
                                                  std::shared_ptr<const graph::Registry> registry) {
  return parse_scene_in(text, source, std::move(registry), nullptr);
}

Result<std::unique_ptr<scene::Scene>> load_scene(const std::filesystem::path& path,
                                                 std::shared_ptr<const graph::Registry> registry) {
  // An ifstream opens a directory and reads nothing, which would be reported
  // as a syntax error at 1:1.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return error(ErrorCode::kIoError, path.string() + ": cannot open: is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) return error(ErrorCode::kIoError, path.string() + ": cannot open: " + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return error(ErrorCode::kIoError, path.string() + ": read failed");
  const std::filesystem::path folder = std::filesystem::absolute(path, ec).parent_path();
  return parse_scene_in(buffer.str(), path.string(), std::move(registry), &folder);
}

namespace {

// One node, as diffable_json() lays out an object at 4 columns in the
// "nodes" array, written as it is read from the graph (the whole file is
// never a JSON document: a baked shot's is hundreds of MB, mostly arrays of
// doubles, which are written element by element).
void write_node(DiffableJsonWriter& w, const Graph& g, NodeId id, const std::filesystem::path* folder) {
  const graph::Node& n = *g.node(id);
  w.text("{\n      \"name\": ");
  w.value(Json(n.name()), 6, false);
  w.text(",\n      \"type\": ");
  w.value(Json(n.type().name()), 6, false);
  w.text(",\n      \"uuid\": ");
  w.value(Json(n.uuid().str()), 6, false);
  if (NodeId p = g.parent(id); p.is_valid()) {
    w.text(",\n      \"parent\": ");
    w.value(Json(g.node(p)->name()), 6, false);
  }
  bool any_attr = false;
  for (AttrIndex a = 0; a < n.type().attr_count(); ++a) {
    const AttrSpec& spec = n.type().attr(a);
    if (!(spec.flags & graph::kInput) || !(spec.flags & graph::kStorable)) continue;
    if (spec.type.value == ValueType::kMessage) continue;
    if (g.source(Plug{id, a, -1})) continue;  // the connection restores it
    const Value& value = n.value(a);
    if (graph::values_identical(value, spec.default_value)) continue;
    w.text(any_attr ? ",\n        " : ",\n      \"attrs\": {\n        ");
    any_attr = true;
    w.key(spec.name);
    w.text(": ");
    if (const auto* doubles = std::get_if<std::vector<double>>(&value); doubles && spec.type.array) {
      // An array of scalars: one line.
      w.text("[");
      for (std::size_t i = 0; i < doubles->size(); ++i) {
        if (i) w.text(", ");
        w.value(encode_double((*doubles)[i]), 8, false);
      }
      w.text("]");
      continue;
    }
    Json v = encode_value(value, spec);
    if (folder && v.is_string() && !v.get_ref<const std::string&>().empty() && is_path_attribute(n.type().name(), spec.name))
      v = path_relative_to(v.get<std::string>(), *folder);
    w.value(v, 8, false);
  }
  if (any_attr) w.text("\n      }");
  if (!n.tags().empty()) {
    Json tags = Json::object();
    for (const auto& [k, v] : n.tags()) tags[k] = v;
    w.text(",\n      \"tags\": ");
    w.value(tags, 6, false);
  }
  w.text("\n    }");
}

// Writes the file node by node, in the layout diffable_json() gives the
// whole document (tests/data/scenes/golden_v1.rigel holds it to the byte):
//   { "rigel", "version", "fps", "time", "nodes": [ ... ], "connections": [ ... ] }
// What is held at a time is the writer's chunk (and one small value).
void write_scene_to(scene::Scene& scene, const std::filesystem::path* folder, std::ostream& out) {
  Graph& g = scene.graph();
  g.evaluate_all();
  DiffableJsonWriter w(out);
  w.text("{\n  \"rigel\": \"scene\",\n  \"version\": ");
  w.value(Json(kSceneFormatVersion), 2, false);
  w.text(",\n  \"fps\": ");
  w.value(Json(g.fps()), 2, false);
  w.text(",\n  \"time\": ");
  w.value(Json(g.time()), 2, false);
  // An array of objects: one element per line, "[]" when empty.
  bool any = false;
  auto next = [&] {
    w.text(any ? ",\n    " : "[\n    ");
    any = true;
  };
  auto close = [&] {
    w.text(any ? "\n  ]" : "[]");
    any = false;
  };
  w.text(",\n  \"nodes\": ");
  for (NodeId id : g.nodes()) {
    next();
    write_node(w, g, id, folder);
  }
  close();
  w.text(",\n  \"connections\": ");
  for (const graph::Connection& c : g.connections()) {
    if (is_hierarchy(g, c)) continue;
    Json jc;
    jc["src"] = g.plug_name(c.src);
    jc["dst"] = g.plug_name(c.dst);
    next();
    w.value(jc, 4, true);
  }
  close();
  w.text("\n}\n");
  w.flush();
}

// An unbuffered stream buffer on a file descriptor (the writers above hand
// it chunks); remembers the errno of a failed write.
class FdStreambuf : public std::streambuf {
 public:
  explicit FdStreambuf(int fd) : fd_(fd) {}
  int error = 0;

 protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    std::streamsize done = 0;
    while (done < n) {
      const ssize_t written = ::write(fd_, s + done, static_cast<std::size_t>(n - done));
      if (written < 0) {
        if (errno == EINTR) continue;
        error = errno;
        return done;
      }
      done += written;
    }
    return done;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }

 private:
  int fd_;
};

// Writes what `produce` writes to `path` atomically: a temporary file beside
// it, written as it is produced, fsync'ed, then renamed over `path`.
Status write_file_atomic_from(const std::filesystem::path& path, const std::function<void(std::ostream&)>& produce) {
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::string name = ".";
  name.append(path.filename().string()).append(".tmp-XXXXXX");
  std::string temp = (dir / name).string();
  int fd = mkstemp(temp.data());
  if (fd < 0) return error(ErrorCode::kIoError, path.string() + ": cannot write: " + std::strerror(errno));
  auto fail = [&](const char* what, int saved) {
    ::close(fd);
    ::unlink(temp.c_str());
    return error(ErrorCode::kIoError, path.string() + ": " + what + ": " + std::strerror(saved));
  };
  {
    FdStreambuf buffer(fd);
    std::ostream stream(&buffer);
    try {
      produce(stream);
      stream.flush();
    } catch (...) {
      ::close(fd);
      ::unlink(temp.c_str());
      throw;
    }
    if (!stream) return fail("write failed", buffer.error != 0 ? buffer.error : EIO);
  }
  // Keep the permissions of the file being replaced; a new file gets 0644.
  struct stat existing;
  const mode_t mode = ::stat(path.c_str(), &existing) == 0 ? (existing.st_mode & 07777) : 0644;
  if (::fchmod(fd, mode) != 0) return fail("chmod failed", errno);
  if (::fsync(fd) != 0) return fail("fsync failed", errno);
  if (::close(fd) != 0) {
    int saved = errno;
    ::unlink(temp.c_str());
    return error(ErrorCode::kIoError, path.string() + ": close failed: " + std::strerror(saved));
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    int saved = errno;
    ::unlink(temp.c_str());
    return error(ErrorCode::kIoError, path.string() + ": rename failed: " + std::strerror(saved));
  }
  return Status::ok();
}

}  // namespace

std::string write_scene(scene::Scene& scene) {
  std::ostringstream out;
  write_scene_to(scene, nullptr, out);
  return std::move(out).str();
}

Status write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  return write_file_atomic_from(path, [&](std::ostream& out) {
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
  });
}

Status save_scene(scene::Scene& scene, const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::path folder = std::filesystem::absolute(path, ec).parent_path();
  return write_file_atomic_from(path, [&](std::ostream& out) { write_scene_to(scene, &folder, out); });
}

}  // namespace rigel::io
