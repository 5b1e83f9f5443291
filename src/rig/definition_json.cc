// The JSON syntax of rig definitions (`.rig.json`, docs/RIG.md), with
// nlohmann-json.
//
// Why a position index: nlohmann-json 3.11.2 (Debian 12) reports the place of
// a syntax error but keeps no places for the values it parsed, and the
// headline requirement of `rigel validate` is that every error names its
// line and column. So after a successful parse, JsonPositions scans the
// (known well-formed) text once more and records, for every value, the
// offset of its first character under its JSON-pointer path
// ("/rig/components/0/guides/1"), and for every object member the offset of
// its key. The same scan finds duplicate keys, which nlohmann-json accepts
// silently (the last one wins).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <initializer_list>
#include <limits>
#include <set>
#include <unordered_map>
#include <utility>

#include "definition_io_internal.h"
#include "rigel/io/json_depth.h"
#include "rigel/io/diffable_json.h"

namespace rigel::rig::detail {
namespace {

using Json = nlohmann::ordered_json;

std::string pointer_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

void append_utf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

// See the file comment. Iterative (an explicit stack), so deep nesting that
// nlohmann-json accepted cannot overflow the call stack here.
class JsonPositions {
 public:
  struct Duplicate {
    std::string key;
    std::size_t offset;
  };

  explicit JsonPositions(std::string_view text) : text_(text) {
    values_.push_back(std::string_view::npos);  // the root, id 0
    keys_.push_back(std::string_view::npos);
    scan();
  }

  std::size_t value(const std::string& pointer) const { return at_id(values_, pointer); }
  std::size_t key(const std::string& pointer) const { return at_id(keys_, pointer); }
  const std::vector<Duplicate>& duplicates() const { return duplicates_; }

 private:
  // Values are kept as a tree (id -> parent id and token), not by their
  // whole pointer text: deep nesting costs memory in proportion to the
  // values, not to their depth.
  struct Frame {
    bool object;
    std::size_t id;
    std::size_t index = 0;
    std::set<std::string> keys;
  };

  std::size_t child_id(std::size_t parent, const std::string& token) {
    std::string k = std::to_string(parent);
    k += '/';
    k += token;
    const auto [it, fresh] = children_.emplace(std::move(k), values_.size());
    if (fresh) {
      values_.push_back(std::string_view::npos);
      keys_.push_back(std::string_view::npos);
    }
    return it->second;
  }

  // The offset recorded in `table` for the value at `pointer`, or npos.
  std::size_t at_id(const std::vector<std::size_t>& table, const std::string& pointer) const {
    std::size_t id = 0;
    std::size_t i = 0;
    while (i < pointer.size()) {
      const std::size_t next = std::min(pointer.find('/', i + 1), pointer.size());
      std::string k = std::to_string(id);
      k += '/';
      k.append(pointer, i + 1, next - i - 1);
      const auto it = children_.find(k);
      if (it == children_.end()) return std::string_view::npos;
      id = it->second;
      i = next;
    }
    return table[id];
  }

  char at(std::size_t i) const { return i < text_.size() ? text_[i] : '\0'; }
  std::size_t ws(std::size_t i) const {
    while (i < text_.size() && (text_[i] == ' ' || text_[i] == '\t' || text_[i] == '\n' || text_[i] == '\r')) ++i;
    return i;
  }

  // The string starting at the quote `i`, decoded; `i` moves past it.
  std::string read_string(std::size_t& i) const {
    std::string out;
    ++i;
    while (i < text_.size() && text_[i] != '"') {
      if (text_[i] != '\\') {
        out += text_[i++];
        continue;
      }
      const char e = at(i + 1);
      i += 2;
      switch (e) {
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          auto hex4 = [&](std::size_t p) {
            std::uint32_t v = 0;
            for (std::size_t k = 0; k < 4; ++k) {
              const char h = at(p + k);
              v = v * 16 + static_cast<std::uint32_t>(h <= '9' ? h - '0' : (h | 0x20) - 'a' + 10);
            }
            return v;
          };
          std::uint32_t cp = hex4(i);
          i += 4;
          if (cp >= 0xD800 && cp < 0xDC00 && at(i) == '\\' && at(i + 1) == 'u') {
            const std::uint32_t low = hex4(i + 2);
            cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
            i += 6;
          }
          append_utf8(out, cp);
          break;
        }
        default: out += e;  // \" \\ \/
      }
    }
    ++i;  // the closing quote
    return out;
  }

  // The member key at `i` of the object on top of `stack`: records it and
  // returns the id of its value; `i` moves to the value.
  std::size_t read_key(std::size_t& i, Frame& frame) {
    const std::size_t key_offset = i;
    const std::string key = read_string(i);
    i = ws(i);
    i = ws(i + 1);  // ':'
    const std::size_t id = child_id(frame.id, pointer_token(key));
    if (!frame.keys.insert(key).second) duplicates_.push_back({key, key_offset});
    keys_[id] = key_offset;
    return id;
  }

  void scan() {
    std::size_t i = 0;
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") i = 3;  // nlohmann-json skips a UTF-8 byte order mark too
    i = ws(i);
    std::vector<Frame> stack;
    std::size_t path = 0;
    bool expect_value = true;
    while (i <= text_.size()) {
      if (expect_value) {
        values_[path] = i;
        const char c = at(i);
        if (c == '{' || c == '[') {
          stack.push_back(Frame{c == '{', path, 0, {}});
          i = ws(i + 1);
          if (at(i) == (c == '{' ? '}' : ']')) {
            ++i;
            stack.pop_back();
            expect_value = false;
          } else if (c == '{') {
            path = read_key(i, stack.back());
          } else {
            path = child_id(stack.back().id, "0");
          }
          continue;
        }
        if (c == '"') {
          read_string(i);
        } else {
          while (i < text_.size() && std::string_view(",]} \t\r\n").find(text_[i]) == std::string_view::npos) ++i;
        }
        expect_value = false;
        continue;
      }
      if (stack.empty()) break;
      i = ws(i);
      Frame& top = stack.back();
      if (at(i) == ',') {
        i = ws(i + 1);
        ++top.index;
        path = top.object ? read_key(i, top) : child_id(top.id, std::to_string(top.index));
        expect_value = true;
      } else {
        ++i;  // '}' or ']'
        stack.pop_back();
        if (i > text_.size()) break;
      }
    }
  }

  std::string_view text_;
  std::vector<std::size_t> values_, keys_;  // by id
  std::unordered_map<std::string, std::size_t> children_;  // "PARENT_ID/TOKEN" -> id
  std::vector<Duplicate> duplicates_;
};


std::string list_text(std::initializer_list<const char*> names) {
  std::string out;
  for (const char* n : names) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

std::string kind_of(const Json& j) {
  if (j.is_boolean()) return "a boolean";
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_array()) return "an array";
  if (j.is_object()) return "an object";
  return "null";
}

class JsonReader {
 public:
  JsonReader(std::string_view text, const std::string& source, const SchemaRegistry& schemas,
             std::vector<Diagnostic>& errors)
      : positions_(text), lines_(text), source_(source), schemas_(schemas), errors_(errors) {
    for (const auto& d : positions_.duplicates())
      error(lines_.at(d.offset), "duplicate key '" + d.key + "' (the last one would win)");
  }

  void read_document(const Json& root, Definition& d) {
    if (!root.is_object()) {
      error(value_at(""), "the file must hold an object {\"rig\": {...}}, not " + kind_of(root));
      return;
    }
    check_keys(root, "", {"rig"}, "the file");
    if (!root.contains("rig")) {
      error(value_at(""), "no \"rig\" key: the file must hold {\"rig\": {...}}");
      return;
    }
    read_rig(root["rig"], "/rig", d);
  }

  // The rest is public for DefinitionJsonParts (below), whose readers use
  // the same members.
  void error(SourceLocation where, std::string message) { errors_.push_back({source_, where, std::move(message)}); }

  SourceLocation value_at(const std::string& path) const {
    const std::size_t offset = positions_.value(path);
    return offset == std::string_view::npos ? SourceLocation{} : lines_.at(offset);
  }
  SourceLocation key_at(const std::string& path) const {
    const std::size_t offset = positions_.key(path);
    return offset == std::string_view::npos ? value_at(path) : lines_.at(offset);
  }
  static std::string child(const std::string& path, std::string_view key) { return path + "/" + pointer_token(key); }
  static std::string child(const std::string& path, std::size_t index) { return path + "/" + std::to_string(index); }

  bool expect(const Json& j, const std::string& path, bool ok, const std::string& what, const char* expected) {
    if (!ok) error(value_at(path), what + " must be " + expected + ", not " + kind_of(j));
    return ok;
  }

  void check_keys(const Json& object, const std::string& path, std::initializer_list<const char*> allowed,
                  const char* what) {
    for (auto it = object.begin(); it != object.end(); ++it) {
      bool known = false;
      for (const char* a : allowed) known |= it.key() == a;
      if (!known)
        error(key_at(child(path, it.key())),
              "unknown key '" + it.key() + "' in " + what + " (expected " + list_text(allowed) + ")");
    }
  }

  // Member readers: absent leaves `out` as it is; a value of the wrong kind
  // is reported at the value and leaves it too.
  void read_string(const Json& object, const std::string& path, const char* key, std::string& out) {
    if (!object.contains(key)) return;
    const Json& v = object[key];
    if (expect(v, child(path, key), v.is_string(), std::string("'") + key + "'", "a string")) out = v.get<std::string>();
  }
  void read_bool(const Json& object, const std::string& path, const char* key, bool& out) {
    if (!object.contains(key)) return;
    const Json& v = object[key];
    if (expect(v, child(path, key), v.is_boolean(), std::string("'") + key + "'", "true or false")) out = v.get<bool>();
  }
  void read_number(const Json& object, const std::string& path, const char* key, double& out) {
    if (!object.contains(key)) return;
    const Json& v = object[key];
    if (expect(v, child(path, key), v.is_number(), std::string("'") + key + "'", "a number")) out = v.get<double>();
  }
  // An array of `n` numbers into `out`.
  bool read_numbers(const Json& v, const std::string& path, const std::string& what, std::size_t n, double* out) {
    bool ok = v.is_array() && v.size() == n;
    if (ok)
      for (const Json& e : v) ok &= e.is_number();
    if (!ok) {
      error(value_at(path), what + " must be an array of " + std::to_string(n) + " numbers" +
                                (n == 3 ? " [x, y, z]" : " [x, y]") + ", not " +
                                (v.is_array() ? "an array of " + std::to_string(v.size()) + " values" : kind_of(v)));
      return false;
    }
    for (std::size_t i = 0; i < n; ++i) out[i] = v[i].get<double>();
    return true;
  }
  void read_vec3(const Json& object, const std::string& path, const char* key, math::Vec3& out) {
    if (!object.contains(key)) return;
    double v[3];
    if (read_numbers(object[key], child(path, key), std::string("'") + key + "'", 3, v)) out = {v[0], v[1], v[2]};
  }
  void read_gui_location(const Json& object, const std::string& path, std::optional<std::pair<double, double>>& out) {
    if (!object.contains("guiLocation")) return;
    double v[2];
    if (read_numbers(object["guiLocation"], child(path, "guiLocation"), "'guiLocation'", 2, v)) out = std::pair{v[0], v[1]};
  }
  // Calls `f(item, item_path)` for each element of array member `key`.
  template <typename F>
  void for_each(const Json& object, const std::string& path, const char* key, F&& f) {
    if (!object.contains(key)) return;
    const Json& a = object[key];
    const std::string a_path = child(path, key);
    if (!expect(a, a_path, a.is_array(), std::string("'") + key + "'", "an array")) return;
    for (std::size_t i = 0; i < a.size(); ++i) f(a[i], child(a_path, i));
  }

  void read_rig(const Json& j, const std::string& path, Definition& d) {
    d.where = value_at(path);
    if (!expect(j, path, j.is_object(), "'rig'", "an object")) return;
    check_keys(j, path, {"name", "version", "guiLocation", "geometry", "features", "data", "components"}, "the rig");
    read_string(j, path, "name", d.name);
    read_string(j, path, "version", d.version);
    read_gui_location(j, path, d.gui_location);
    for_each(j, path, "geometry", [&](const Json& g, const std::string& p) {
      if (!expect(g, p, g.is_object(), "a geometry entry", "an object {\"file\", \"name\"}")) return;
      Geometry geo;
      geo.where = value_at(p);
      check_keys(g, p, {"file", "name"}, "geometry");
      read_string(g, p, "file", geo.file);
      read_string(g, p, "name", geo.name);
      d.geometry.push_back(std::move(geo));
    });
    for_each(j, path, "features", [&](const Json& f, const std::string& p) { read_feature(f, p, d.features); });
    for_each(j, path, "data", [&](const Json& x, const std::string& p) {
      if (!expect(x, p, x.is_object(), "a data entry", "an object {\"kind\", \"file\"}")) return;
      DataImport entry;
      entry.where = value_at(p);
      check_keys(x, p, {"kind", "file"}, "a data entry");
      read_string(x, p, "kind", entry.kind);
      read_string(x, p, "file", entry.file);
      d.data.push_back(std::move(entry));
    });
    for_each(j, path, "components", [&](const Json& c, const std::string& p) { read_component(c, p, d.components, 1); });
  }

  void read_feature(const Json& j, const std::string& path, std::vector<Feature>& out) {
    if (!expect(j, path, j.is_object(), "a feature", "an object {\"name\", \"enabled\", \"switches\"}")) return;
    Feature f;
    f.where = value_at(path);
    check_keys(j, path, {"name", "enabled", "switches"}, "a feature");
    read_string(j, path, "name", f.name);
    read_bool(j, path, "enabled", f.enabled);
    for_each(j, path, "switches", [&](const Json& s, const std::string& p) {
      if (!expect(s, p, s.is_object(), "a switch", "an object {\"name\", \"enabled\"}")) return;
      FeatureSwitch sw;
      sw.where = value_at(p);
      check_keys(s, p, {"name", "enabled"}, "a switch");
      read_string(s, p, "name", sw.name);
      read_bool(s, p, "enabled", sw.enabled);
      f.switches.push_back(std::move(sw));
    });
    out.push_back(std::move(f));
  }

  void read_component(const Json& j, const std::string& path, std::vector<Component>& out, std::size_t depth) {
    if (depth > kMaxComponentDepth) {
      error(value_at(path), "components nest deeper than " + std::to_string(kMaxComponentDepth) + " levels (the limit)");
      return;
    }
    if (!expect(j, path, j.is_object(), "a component", "an object")) return;
    Component c;
    c.where = value_at(path);
    check_keys(j, path,
               {"type", "name", "side", "version", "rigId", "attach", "after", "guiLocation", "guides", "controls",
                "params", "features", "children"},
               "a component");
    read_string(j, path, "type", c.type);
    read_string(j, path, "name", c.name);
    std::string side;
    read_string(j, path, "side", side);
    if (!side.empty() || (j.contains("side") && j["side"].is_string())) {
      if (const auto s = side_from_name(side)) {
        c.side = *s;
      } else {
        error(value_at(child(path, "side")), "'side': unknown side '" + side + "' (expected C, L or R)");
      }
    }
    read_string(j, path, "version", c.version);
    read_string(j, path, "rigId", c.rig_id);
    read_string(j, path, "attach", c.attach);
    for_each(j, path, "after", [&](const Json& id, const std::string& p) {
      if (expect(id, p, id.is_string(), "an 'after' entry", "a rigId string")) c.after.push_back(id.get<std::string>());
    });
    read_gui_location(j, path, c.gui_location);
    for_each(j, path, "guides", [&](const Json& g, const std::string& p) {
      if (!expect(g, p, g.is_object(), "a guide", "an object")) return;
      Guide guide;
      guide.where = value_at(p);
      check_keys(g, p, {"name", "joint", "translate", "rotate", "scale"}, "a guide");
      read_string(g, p, "name", guide.name);
      read_string(g, p, "joint", guide.joint);
      read_vec3(g, p, "translate", guide.translate);
      read_vec3(g, p, "rotate", guide.rotate);
      read_vec3(g, p, "scale", guide.scale);
      c.guides.push_back(std::move(guide));
    });
    for_each(j, path, "controls", [&](const Json& s, const std::string& p) {
      if (!expect(s, p, s.is_object(), "a control", "an object")) return;
      ControlStyle style;
      style.where = value_at(p);
      check_keys(s, p, {"role", "shape", "color", "size"}, "a control");
      read_string(s, p, "role", style.role);
      read_string(s, p, "shape", style.shape);
      read_string(s, p, "color", style.color);
      read_number(s, p, "size", style.size);
      c.controls.push_back(std::move(style));
    });
    if (j.contains("params")) {
      const Json& params = j["params"];
      const std::string p_path = child(path, "params");
      if (expect(params, p_path, params.is_object(), "'params'", "an object {NAME: VALUE}")) {
        for (auto it = params.begin(); it != params.end(); ++it) {
          const ParamSpec* spec = find_param_spec(schemas_, c.type, it.key());
          if (auto p = read_param(it.key(), it.value(), child(p_path, it.key()), spec)) c.params.push_back(std::move(*p));
        }
      }
    }
    for_each(j, path, "features", [&](const Json& f, const std::string& p) { read_feature(f, p, c.features); });
    for_each(j, path, "children", [&](const Json& ch, const std::string& p) { read_component(ch, p, c.children, depth + 1); });
    out.push_back(std::move(c));
  }

  // A parameter typed by its JSON kind; an integer given for a double
  // parameter becomes a double. Anything else that does not fit the schema
  // is kept as it is for validate() to report.
  std::optional<Param> read_param(const std::string& name, const Json& v, const std::string& path,
                                  const ParamSpec* spec) {
    Param p;
    p.name = name;
    p.where = key_at(path);
    if (v.is_boolean()) {
      p.value = v.get<bool>();
    } else if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      error(value_at(path), "parameter '" + name + "': " + v.dump() + " is out of range");
      return std::nullopt;
    } else if (v.is_number_integer()) {
      const std::int64_t i = v.get<std::int64_t>();
      if (spec && spec->type == ParamType::kDouble) p.value = static_cast<double>(i);
      else p.value = i;
    } else if (v.is_number_float()) {
      p.value = v.get<double>();
    } else if (v.is_string()) {
      p.value = v.get<std::string>();
    } else if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number()) {
      p.value = math::Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    } else {
      error(value_at(path), "parameter '" + name + "' must be true/false, a number, a string or [x, y, z], not " +
                                (v.is_array() ? "an array of " + std::to_string(v.size()) + " values" : kind_of(v)));
      return std::nullopt;
    }
    return p;
  }

 private:
  JsonPositions positions_;
  LineIndex lines_;
  const std::string& source_;
  const SchemaRegistry& schemas_;
  std::vector<Diagnostic>& errors_;
};

// ---- writing -------------------------------------------------------------------

Json vec3_json(const math::Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json feature_json(const Feature& f) {
  Json j = Json::object();
  j["name"] = f.name;
  j["enabled"] = f.enabled;
  if (!f.switches.empty()) {
    Json s = Json::array();
    for (const FeatureSwitch& sw : f.switches) s.push_back(Json{{"name", sw.name}, {"enabled", sw.enabled}});
    j["switches"] = std::move(s);
  }
  return j;
}

Json param_json(const ParamValue& value) {
  if (const auto* b = std::get_if<bool>(&value)) return *b;
  if (const auto* i = std::get_if<std::int64_t>(&value)) return *i;
  if (const auto* d = std::get_if<double>(&value)) return *d;
  if (const auto* v = std::get_if<math::Vec3>(&value)) return vec3_json(*v);
  return std::get<std::string>(value);
}

Json component_json(const Component& c) {
  Json j = Json::object();
  j["type"] = c.type;
  j["name"] = c.name;
  j["side"] = side_name(c.side);
  j["version"] = c.version;
  if (!c.rig_id.empty()) j["rigId"] = c.rig_id;
  if (!c.attach.empty()) j["attach"] = c.attach;
  if (!c.after.empty()) j["after"] = c.after;
  if (c.gui_location) j["guiLocation"] = Json::array({c.gui_location->first, c.gui_location->second});
  if (!c.guides.empty()) {
    Json a = Json::array();
    for (const Guide& g : c.guides) {
      Json e = Json::object();
      if (!g.name.empty()) e["name"] = g.name;
      if (!g.joint.empty()) e["joint"] = g.joint;
      if (g.translate != math::Vec3::Zero()) e["translate"] = vec3_json(g.translate);
      if (g.rotate != math::Vec3::Zero()) e["rotate"] = vec3_json(g.rotate);
      if (g.scale != math::Vec3::Ones()) e["scale"] = vec3_json(g.scale);
      a.push_back(std::move(e));
    }
    j["guides"] = std::move(a);
  }
  if (!c.controls.empty()) {
    Json a = Json::array();
    for (const ControlStyle& s : c.controls) {
      Json e = Json::object();
      e["role"] = s.role;
      if (!s.shape.empty()) e["shape"] = s.shape;
      if (!s.color.empty()) e["color"] = s.color;
      e["size"] = s.size;
      a.push_back(std::move(e));
    }
    j["controls"] = std::move(a);
  }
  if (!c.params.empty()) {
    Json o = Json::object();
    for (const Param& p : c.params) o[p.name] = param_json(p.value);
    j["params"] = std::move(o);
  }
  if (!c.features.empty()) {
    Json a = Json::array();
    for (const Feature& f : c.features) a.push_back(feature_json(f));
    j["features"] = std::move(a);
  }
  if (!c.children.empty()) {
    Json a = Json::array();
    for (const Component& child : c.children) a.push_back(component_json(child));
    j["children"] = std::move(a);
  }
  return j;
}

std::string scalar_text(const Json& j) {
  if (j.is_number_float()) return format_double_json(j.get<double>());
  // Invalid UTF-8 (possible in text that came from XML) is replaced, not thrown.
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace

std::optional<Json> DefinitionJsonParts::parse(std::string_view text, const std::string& source,
                                               std::vector<Diagnostic>& errors) {
  if (const std::size_t deep = io::json_too_deep(text, kMaxTextDepth); deep != std::string_view::npos) {
    errors.push_back({source, LineIndex(text).at(deep),
                      "JSON arrays and objects nest deeper than " + std::to_string(kMaxTextDepth) +
                          " levels (the limit)"});
    return std::nullopt;
  }
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based: the character where the parser stopped.
    const LineIndex lines(text);
    std::string message = e.what();
    if (const std::size_t colon = message.find(": "); message.rfind("[json.exception", 0) == 0 && colon != std::string::npos)
      message = message.substr(colon + 2);
    errors.push_back({source, lines.at(e.byte > 0 ? e.byte - 1 : 0), "JSON " + message});
    return std::nullopt;
  }
}

struct DefinitionJsonParts::Impl {
  JsonReader reader;
};

DefinitionJsonParts::DefinitionJsonParts(std::string_view text, const std::string& source,
                                         const SchemaRegistry& schemas, std::vector<Diagnostic>& errors)
    : impl_(std::make_unique<Impl>(Impl{JsonReader(text, source, schemas, errors)})) {}
DefinitionJsonParts::~DefinitionJsonParts() = default;

void DefinitionJsonParts::read_rig(const Json& j, const std::string& pointer, Definition& out) {
  impl_->reader.read_rig(j, pointer, out);
}
void DefinitionJsonParts::read_component(const Json& j, const std::string& pointer, std::vector<Component>& out) {
  impl_->reader.read_component(j, pointer, out, 1);
}
std::optional<ParamValue> DefinitionJsonParts::read_value(const std::string& name, const Json& j,
                                                          const std::string& pointer, const ParamSpec* spec) {
  auto p = impl_->reader.read_param(name, j, pointer, spec);
  if (!p) return std::nullopt;
  return std::move(p->value);
}
void DefinitionJsonParts::error(const std::string& pointer, std::string message) {
  impl_->reader.error(impl_->reader.value_at(pointer), std::move(message));
}
void DefinitionJsonParts::key_error(const std::string& pointer, std::string message) {
  impl_->reader.error(impl_->reader.key_at(pointer), std::move(message));
}
SourceLocation DefinitionJsonParts::at(const std::string& pointer) const { return impl_->reader.value_at(pointer); }
void DefinitionJsonParts::check_keys(const Json& object, const std::string& pointer,
                                     std::initializer_list<const char*> allowed, const char* what) {
  impl_->reader.check_keys(object, pointer, allowed, what);
}
Json DefinitionJsonParts::component_json(const Component& component) { return rigel::rig::detail::component_json(component); }
std::string DefinitionJsonParts::scalar_text(const Json& j) { return rigel::rig::detail::scalar_text(j); }

ParseResult parse_json(std::string_view text, const std::string& source, const SchemaRegistry& schemas, bool* fatal) {
  ParseResult result;
  std::optional<Json> root = DefinitionJsonParts::parse(text, source, result.errors);
  if (!root) {
    *fatal = true;
    return result;
  }
  JsonReader reader(text, source, schemas, result.errors);
  reader.read_document(*root, result.definition);
  return result;
}

Json DefinitionJsonParts::rig_json(const Definition& d) {
  Json rig = Json::object();
  rig["name"] = d.name;
  rig["version"] = d.version;
  if (d.gui_location) rig["guiLocation"] = Json::array({d.gui_location->first, d.gui_location->second});
  if (!d.geometry.empty()) {
    Json a = Json::array();
    for (const Geometry& g : d.geometry) {
      Json e = Json::object();
      e["file"] = g.file;
      if (!g.name.empty()) e["name"] = g.name;
      a.push_back(std::move(e));
    }
    rig["geometry"] = std::move(a);
  }
  if (!d.features.empty()) {
    Json a = Json::array();
    for (const Feature& f : d.features) a.push_back(feature_json(f));
    rig["features"] = std::move(a);
  }
  if (!d.data.empty()) {
    Json a = Json::array();
    for (const DataImport& x : d.data) a.push_back(Json{{"kind", x.kind}, {"file", x.file}});
    rig["data"] = std::move(a);
  }
  return rig;
}

std::string write_json(const Definition& d) {
  Json rig = DefinitionJsonParts::rig_json(d);
  if (!d.components.empty()) {
    Json a = Json::array();
    for (const Component& c : d.components) a.push_back(component_json(c));
    rig["components"] = std::move(a);
  }
  Json root = Json::object();
  root["rig"] = std::move(rig);
  // Flat objects in arrays (a guide, a control, a switch, a geometry or data entry)
  // go on one line each.
  return io::diffable_json(root, {.inline_flat_objects_in_arrays = true, .scalar = scalar_text});
}

}  // namespace rigel::rig::detail
