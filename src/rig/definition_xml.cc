// The XML syntax of rig definitions (`.rig.xml`, docs/RIG.md), with pugixml.
//
// pugixml reports the offset of each element (`offset_debug()`, the first
// character of its name) but not of attributes, so the reader scans each
// start tag of the original text for its attributes' places: a message about
// an attribute points at its name, one about its value at the value's first
// character. The scan also finds duplicate attributes, which pugixml accepts.
#include <pugixml.hpp>

#include <algorithm>
#include <initializer_list>
#include <utility>

#include "definition_io_internal.h"

namespace rigel::rig::detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::string list_text(std::initializer_list<const char*> names) {
  std::string out;
  for (const char* n : names) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

class XmlReader {
 public:
  XmlReader(std::string_view text, const std::string& source, const SchemaRegistry& schemas,
            std::vector<Diagnostic>& errors)
      : text_(text), lines_(text), source_(source), schemas_(schemas), errors_(errors) {}

  void read_document(const pugi::xml_document& doc, Definition& d) {
    pugi::xml_node rig;
    for (pugi::xml_node n : doc.children()) {
      if (n.type() == pugi::node_element) {
        if (!rig && std::string_view(n.name()) == "rig") {
          rig = n;
        } else if (!rig) {
          error(at(n), "the root element must be <rig>, not <" + std::string(n.name()) + ">");
          return;
        } else {
          error(at(n), "unexpected element <" + std::string(n.name()) + "> after <rig>: a file holds one rig");
        }
      } else if (n.type() == pugi::node_pcdata || n.type() == pugi::node_cdata) {
        error(at(n), "unexpected text outside <rig>");
      }
    }
    if (!rig) {
      error({1, 1}, "no <rig> element");
      return;
    }
    read_rig(rig, d);
  }

 private:
  struct Attr {
    std::string name;
    std::size_t name_offset = 0;
    std::size_t value_offset = 0;
  };

  void error(SourceLocation where, std::string message) { errors_.push_back({source_, where, std::move(message)}); }

  // The '<' of an element (pugixml's offset is its name's first character).
  SourceLocation at(pugi::xml_node n) const {
    const std::ptrdiff_t offset = n.offset_debug();
    if (offset < 0) return {};
    std::size_t o = static_cast<std::size_t>(offset);
    if (n.type() == pugi::node_element && o > 0) --o;
    // Text: its first character that is not white space.
    if (n.type() == pugi::node_pcdata)
      while (o < text_.size() && is_space(text_[o])) ++o;
    return lines_.at(o);
  }

  // The attributes of `n`'s start tag, in order, from the original text.
  // pugixml has checked the syntax, so the scan needs no error handling
  // beyond staying inside the text.
  std::vector<Attr> scan_attrs(pugi::xml_node n) const {
    std::vector<Attr> out;
    const std::ptrdiff_t offset = n.offset_debug();
    if (offset < 0) return out;
    std::size_t i = static_cast<std::size_t>(offset);
    const std::size_t size = text_.size();
    while (i < size && !is_space(text_[i]) && text_[i] != '/' && text_[i] != '>') ++i;  // the element name
    while (i < size) {
      while (i < size && is_space(text_[i])) ++i;
      if (i >= size || text_[i] == '/' || text_[i] == '>') break;
      Attr a;
      a.name_offset = i;
      while (i < size && !is_space(text_[i]) && text_[i] != '=') ++i;
      a.name = std::string(text_.substr(a.name_offset, i - a.name_offset));
      while (i < size && text_[i] != '"' && text_[i] != '\'') ++i;
      if (i >= size) break;
      const char quote = text_[i++];
      a.value_offset = i;
      while (i < size && text_[i] != quote) ++i;
      ++i;
      out.push_back(std::move(a));
    }
    return out;
  }

  // Reports unknown and duplicate attributes; returns the places of the
  // attributes for later messages.
  std::vector<Attr> check_attrs(pugi::xml_node n, std::initializer_list<const char*> allowed) {
    std::vector<Attr> attrs = scan_attrs(n);
    for (std::size_t i = 0; i < attrs.size(); ++i) {
      const Attr& a = attrs[i];
      bool known = false;
      for (const char* name : allowed) known |= a.name == name;
      if (!known) {
        error(lines_.at(a.name_offset), "unknown attribute '" + a.name + "' on <" + n.name() + "> (expected " +
                                            list_text(allowed) + ")");
        continue;
      }
      for (std::size_t j = 0; j < i; ++j) {
        if (attrs[j].name == a.name) {
          error(lines_.at(a.name_offset), "duplicate attribute '" + a.name + "' on <" + n.name() + ">");
          break;
        }
      }
    }
    return attrs;
  }

  SourceLocation value_at(pugi::xml_node n, const std::vector<Attr>& attrs, const char* name) const {
    for (const Attr& a : attrs)
      if (a.name == name) return lines_.at(a.value_offset);
    return at(n);
  }

  // Element children; text between them is an error (comments are skipped
  // by the parser).
  template <typename F>
  void children(pugi::xml_node n, F&& on_element) {
    for (pugi::xml_node c : n.children()) {
      if (c.type() == pugi::node_element) {
        on_element(c, std::string_view(c.name()));
      } else if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) {
        error(at(c), std::string("unexpected text in <") + n.name() + ">");
      }
    }
  }

  void unknown_element(pugi::xml_node parent, pugi::xml_node c, std::initializer_list<const char*> allowed) {
    error(at(c), "unknown element <" + std::string(c.name()) + "> in <" + parent.name() + "> (expected " +
                     list_text(allowed) + ")");
  }

  // Typed attribute readers: absent leaves `out` as it is; a bad value is
  // reported at the value and leaves it too.
  void read_bool(pugi::xml_node n, const std::vector<Attr>& attrs, const char* name, bool& out) {
    const pugi::xml_attribute a = n.attribute(name);
    if (!a) return;
    const std::string_view v = a.value();
    if (v == "true") {
      out = true;
    } else if (v == "false") {
      out = false;
    } else {
      error(value_at(n, attrs, name),
            "<" + std::string(n.name()) + "> " + name + ": '" + std::string(v) + "' is not true or false");
    }
  }

  void read_double(pugi::xml_node n, const std::vector<Attr>& attrs, const char* name, double& out) {
    const pugi::xml_attribute a = n.attribute(name);
    if (!a) return;
    if (const auto d = parse_double(a.value())) {
      out = *d;
    } else {
      error(value_at(n, attrs, name), "<" + std::string(n.name()) + "> " + name + ": bad number '" + a.value() + "'");
    }
  }

  void read_vec3(pugi::xml_node n, const std::vector<Attr>& attrs, const char* name, math::Vec3& out) {
    const pugi::xml_attribute a = n.attribute(name);
    if (!a) return;
    if (const auto v = parse_vec3(a.value())) {
      out = *v;
    } else {
      error(value_at(n, attrs, name), "<" + std::string(n.name()) + "> " + name + ": expected three numbers \"x y z\", got '" +
                                          a.value() + "'");
    }
  }

  void read_gui_location(pugi::xml_node n, const std::vector<Attr>& attrs,
                         std::optional<std::pair<double, double>>& out) {
    const pugi::xml_attribute a = n.attribute("guiLocation");
    if (!a) return;
    if (const auto p = parse_pair(a.value())) {
      out = *p;
    } else {
      error(value_at(n, attrs, "guiLocation"),
            "<" + std::string(n.name()) + "> guiLocation: expected two numbers \"x,y\", got '" + a.value() + "'");
    }
  }

  void read_rig(pugi::xml_node n, Definition& d) {
    d.where = at(n);
    const auto attrs = check_attrs(n, {"name", "version", "guiLocation"});
    d.name = n.attribute("name").value();
    if (const pugi::xml_attribute v = n.attribute("version")) d.version = v.value();
    read_gui_location(n, attrs, d.gui_location);
    children(n, [&](pugi::xml_node c, std::string_view name) {
      if (name == "geo") {
        d.geometry.push_back(read_geo(c));
      } else if (name == "feature") {
        d.features.push_back(read_feature(c));
      } else if (name == "component") {
        d.components.push_back(read_component(c));
      } else {
        unknown_element(n, c, {"geo", "feature", "component"});
      }
    });
  }

  Geometry read_geo(pugi::xml_node n) {
    Geometry g;
    g.where = at(n);
    check_attrs(n, {"file", "name"});
    g.file = n.attribute("file").value();
    g.name = n.attribute("name").value();
    children(n, [&](pugi::xml_node c, std::string_view) { unknown_element(n, c, {}); });
    return g;
  }

  Feature read_feature(pugi::xml_node n) {
    Feature f;
    f.where = at(n);
    const auto attrs = check_attrs(n, {"name", "enabled"});
    f.name = n.attribute("name").value();
    read_bool(n, attrs, "enabled", f.enabled);
    children(n, [&](pugi::xml_node c, std::string_view name) {
      if (name != "switch") {
        unknown_element(n, c, {"switch"});
        return;
      }
      FeatureSwitch s;
      s.where = at(c);
      const auto switch_attrs = check_attrs(c, {"name", "enabled"});
      s.name = c.attribute("name").value();
      read_bool(c, switch_attrs, "enabled", s.enabled);
      children(c, [&](pugi::xml_node cc, std::string_view) { unknown_element(c, cc, {}); });
      f.switches.push_back(std::move(s));
    });
    return f;
  }

  Component read_component(pugi::xml_node n) {
    Component c;
    c.where = at(n);
    const auto attrs = check_attrs(n, {"type", "name", "side", "version", "rigId", "attach", "guiLocation"});
    c.type = n.attribute("type").value();
    c.name = n.attribute("name").value();
    if (const pugi::xml_attribute side = n.attribute("side")) {
      if (const auto s = side_from_name(side.value())) {
        c.side = *s;
      } else {
        error(value_at(n, attrs, "side"),
              "<component> side: unknown side '" + std::string(side.value()) + "' (expected C, L or R)");
      }
    }
    if (const pugi::xml_attribute v = n.attribute("version")) c.version = v.value();
    c.rig_id = n.attribute("rigId").value();
    c.attach = n.attribute("attach").value();
    read_gui_location(n, attrs, c.gui_location);
    children(n, [&](pugi::xml_node e, std::string_view name) {
      if (name == "guide") {
        c.guides.push_back(read_guide(e));
      } else if (name == "control") {
        c.controls.push_back(read_control(e));
      } else if (name == "param") {
        if (auto p = read_param(e, c.type)) c.params.push_back(std::move(*p));
      } else if (name == "feature") {
        c.features.push_back(read_feature(e));
      } else if (name == "component") {
        c.children.push_back(read_component(e));
      } else {
        unknown_element(n, e, {"guide", "control", "param", "feature", "component"});
      }
    });
    return c;
  }

  Guide read_guide(pugi::xml_node n) {
    Guide g;
    g.where = at(n);
    const auto attrs = check_attrs(n, {"name", "joint", "translate", "rotate", "scale"});
    g.name = n.attribute("name").value();
    g.joint = n.attribute("joint").value();
    read_vec3(n, attrs, "translate", g.translate);
    read_vec3(n, attrs, "rotate", g.rotate);
    read_vec3(n, attrs, "scale", g.scale);
    children(n, [&](pugi::xml_node c, std::string_view) { unknown_element(n, c, {}); });
    return g;
  }

  ControlStyle read_control(pugi::xml_node n) {
    ControlStyle s;
    s.where = at(n);
    const auto attrs = check_attrs(n, {"role", "shape", "color", "size"});
    s.role = n.attribute("role").value();
    s.shape = n.attribute("shape").value();
    s.color = n.attribute("color").value();
    read_double(n, attrs, "size", s.size);
    children(n, [&](pugi::xml_node c, std::string_view) { unknown_element(n, c, {}); });
    return s;
  }

  std::optional<Param> read_param(pugi::xml_node n, const std::string& type) {
    check_attrs(n, {"name", "value"});
    children(n, [&](pugi::xml_node c, std::string_view) { unknown_element(n, c, {}); });
    const pugi::xml_attribute name = n.attribute("name"), value = n.attribute("value");
    if (!name || !value) {
      error(at(n), std::string("<param> needs ") + (!name ? "a name" : "a value") + " attribute");
      return std::nullopt;
    }
    Param p;
    p.where = at(n);
    p.name = name.value();
    p.value = param_from_text(value.value(), find_param_spec(schemas_, type, p.name));
    return p;
  }

  std::string_view text_;
  LineIndex lines_;
  const std::string& source_;
  const SchemaRegistry& schemas_;
  std::vector<Diagnostic>& errors_;
};

// ---- writing -------------------------------------------------------------------

void escape_into(std::string& out, std::string_view text) {
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      // Attribute values normalise raw whitespace to spaces: keep it as references.
      case '\n': out += "&#10;"; break;
      case '\r': out += "&#13;"; break;
      case '\t': out += "&#9;"; break;
      default: out += c;
    }
  }
}

class XmlWriter {
 public:
  using Attrs = std::vector<std::pair<const char*, std::string>>;

  // `<name a="..." ...` then ">" (children follow) or "/>".
  void open(int depth, const char* name, const Attrs& attrs, bool has_children) {
    out_.append(static_cast<std::size_t>(2 * depth), ' ');
    out_ += '<';
    out_ += name;
    for (const auto& [key, value] : attrs) {
      out_ += ' ';
      out_ += key;
      out_ += "=\"";
      escape_into(out_, value);
      out_ += '"';
    }
    out_ += has_children ? ">\n" : "/>\n";
  }
  void close(int depth, const char* name) {
    out_.append(static_cast<std::size_t>(2 * depth), ' ');
    out_ += "</";
    out_ += name;
    out_ += ">\n";
  }

  void feature(int depth, const Feature& f) {
    open(depth, "feature", {{"name", f.name}, {"enabled", f.enabled ? "true" : "false"}}, !f.switches.empty());
    for (const FeatureSwitch& s : f.switches)
      open(depth + 1, "switch", {{"name", s.name}, {"enabled", s.enabled ? "true" : "false"}}, false);
    if (!f.switches.empty()) close(depth, "feature");
  }

  void component(int depth, const Component& c) {
    Attrs attrs = {{"type", c.type}, {"name", c.name}, {"side", side_name(c.side)}, {"version", c.version}};
    if (!c.rig_id.empty()) attrs.emplace_back("rigId", c.rig_id);
    if (!c.attach.empty()) attrs.emplace_back("attach", c.attach);
    if (c.gui_location) attrs.emplace_back("guiLocation", pair_text(*c.gui_location));
    const bool has_children = !c.guides.empty() || !c.controls.empty() || !c.params.empty() || !c.features.empty() ||
                              !c.children.empty();
    open(depth, "component", attrs, has_children);
    for (const Guide& g : c.guides) {
      Attrs a;
      if (!g.name.empty()) a.emplace_back("name", g.name);
      if (!g.joint.empty()) a.emplace_back("joint", g.joint);
      if (g.translate != math::Vec3::Zero()) a.emplace_back("translate", vec3_text(g.translate));
      if (g.rotate != math::Vec3::Zero()) a.emplace_back("rotate", vec3_text(g.rotate));
      if (g.scale != math::Vec3::Ones()) a.emplace_back("scale", vec3_text(g.scale));
      open(depth + 1, "guide", a, false);
    }
    for (const ControlStyle& s : c.controls) {
      Attrs a = {{"role", s.role}};
      if (!s.shape.empty()) a.emplace_back("shape", s.shape);
      if (!s.color.empty()) a.emplace_back("color", s.color);
      a.emplace_back("size", format_double(s.size));
      open(depth + 1, "control", a, false);
    }
    for (const Param& p : c.params) open(depth + 1, "param", {{"name", p.name}, {"value", param_text(p.value)}}, false);
    for (const Feature& f : c.features) feature(depth + 1, f);
    for (const Component& child : c.children) component(depth + 1, child);
    if (has_children) close(depth, "component");
  }

  std::string rig(const Definition& d) {
    out_ = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    Attrs attrs = {{"name", d.name}, {"version", d.version}};
    if (d.gui_location) attrs.emplace_back("guiLocation", pair_text(*d.gui_location));
    const bool has_children = !d.geometry.empty() || !d.features.empty() || !d.components.empty();
    open(0, "rig", attrs, has_children);
    for (const Geometry& g : d.geometry) {
      Attrs a = {{"file", g.file}};
      if (!g.name.empty()) a.emplace_back("name", g.name);
      open(1, "geo", a, false);
    }
    for (const Feature& f : d.features) feature(1, f);
    for (const Component& c : d.components) component(1, c);
    if (has_children) close(0, "rig");
    return std::move(out_);
  }

 private:
  std::string out_;
};

}  // namespace

ParseResult parse_xml(std::string_view text, const std::string& source, const SchemaRegistry& schemas, bool* fatal) {
  ParseResult result;
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) {
    const LineIndex lines(text);
    result.errors.push_back({source, lines.at(static_cast<std::size_t>(std::max<std::ptrdiff_t>(parsed.offset, 0))),
                             std::string("XML syntax error: ") + parsed.description()});
    *fatal = true;
    return result;
  }
  XmlReader reader(text, source, schemas, result.errors);
  reader.read_document(doc, result.definition);
  return result;
}

std::string write_xml(const Definition& definition) { return XmlWriter().rig(definition); }

}  // namespace rigel::rig::detail
