// The XML syntax of rig definitions (`.rig.xml`, docs/RIG.md), with pugixml.
//
// pugixml reports the offset of each element (`offset_debug()`, the first
// character of its name) but not of attributes, so the reader scans each
// start tag of the original text for its attributes' places: a message about
// an attribute points at its name, one about its value at the value's first
// character. The scan also finds duplicate attributes, which pugixml accepts.
#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
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

// ---- well-formedness -------------------------------------------------------------
//
// pugixml is a forgiving parser: it accepts "--" inside comments, an XML
// declaration anywhere, '<' and undefined entity references in attribute
// values, references to characters XML does not allow, control characters
// and bad UTF-8, and it reports an unclosed element at the end of the file.
// This pass over the raw text refuses what XML 1.0 refuses (and a DOCTYPE:
// rig definitions declare no entities), names the open tag an end tag does
// not match or that is never closed, and bounds the nesting (kMaxTextDepth)
// before pugixml builds anything.

struct XmlProblem {
  std::size_t offset;
  std::string message;
};

bool is_name_start(unsigned char c) { return std::isalpha(c) || c == '_' || c == ':' || c >= 0x80; }
bool is_name_char(unsigned char c) { return is_name_start(c) || std::isdigit(c) || c == '-' || c == '.'; }

// XML 1.0's Char production.
bool is_xml_char(std::uint32_t cp) {
  return cp == 0x9 || cp == 0xA || cp == 0xD || (cp >= 0x20 && cp <= 0xD7FF) || (cp >= 0xE000 && cp <= 0xFFFD) ||
         (cp >= 0x10000 && cp <= 0x10FFFF);
}

std::string code_point_text(std::uint32_t cp) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "U+%04X", static_cast<unsigned>(cp));
  return buffer;
}

// Every character is valid UTF-8 and one XML allows.
std::optional<XmlProblem> check_characters(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::uint32_t cp = c;
    std::size_t n = 1;
    if (c >= 0x80) {
      n = c >= 0xF0 && c < 0xF5 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
      if (n == 0 || i + n > text.size()) return XmlProblem{i, "invalid UTF-8"};
      cp = c & (n == 2 ? 0x1F : n == 3 ? 0x0F : 0x07);
      for (std::size_t k = 1; k < n; ++k) {
        const auto d = static_cast<unsigned char>(text[i + k]);
        if ((d & 0xC0) != 0x80) return XmlProblem{i, "invalid UTF-8"};
        cp = (cp << 6) | (d & 0x3F);
      }
      if ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
        return XmlProblem{i, "invalid UTF-8 (an overlong or out-of-range sequence)"};
    }
    if (!is_xml_char(cp)) return XmlProblem{i, "character " + code_point_text(cp) + " is not allowed in XML"};
    i += n;
  }
  return std::nullopt;
}

// The reference at text[i] == '&' (in character data or an attribute value):
// a predefined entity or a character reference to a character XML allows.
std::optional<XmlProblem> check_reference(std::string_view text, std::size_t i, std::size_t& end) {
  const std::size_t semi = text.find(';', i);
  const std::size_t stop = text.find_first_of("<&\"' \t\r\n>", i + 1);
  if (semi == std::string_view::npos || (stop != std::string_view::npos && stop < semi))
    return XmlProblem{i, "'&' must start a reference (&amp; &lt; &gt; &quot; &apos; &#N; &#xN;)"};
  const std::string_view ref = text.substr(i + 1, semi - i - 1);
  end = semi + 1;
  if (ref == "lt" || ref == "gt" || ref == "amp" || ref == "quot" || ref == "apos") return std::nullopt;
  if (ref.size() >= 2 && ref[0] == '#') {
    const bool hex = ref[1] == 'x';
    const std::string_view digits = ref.substr(hex ? 2 : 1);
    std::uint64_t cp = 0;
    bool ok = !digits.empty() && digits.size() <= 8;
    for (char d : digits) {
      if (!ok) break;
      const int v = std::isdigit(static_cast<unsigned char>(d)) ? d - '0'
                    : hex && std::isxdigit(static_cast<unsigned char>(d)) ? (std::tolower(static_cast<unsigned char>(d)) - 'a' + 10)
                                                                          : -1;
      ok = v >= 0;
      cp = cp * (hex ? 16 : 10) + static_cast<std::uint64_t>(v < 0 ? 0 : v);
    }
    if (!ok) return XmlProblem{i, "bad character reference '&" + std::string(ref) + ";'"};
    if (cp > 0x10FFFF || !is_xml_char(static_cast<std::uint32_t>(cp)))
      return XmlProblem{i, "'&" + std::string(ref) + ";' refers to a character XML does not allow"};
    return std::nullopt;
  }
  return XmlProblem{i, "undefined entity '&" + std::string(ref) + ";' (rig definitions declare none)"};
}

std::optional<XmlProblem> check_well_formed(std::string_view text) {
  if (auto p = check_characters(text)) return p;
  std::size_t i = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  const std::size_t start = i;
  struct Open {
    std::string_view name;
    std::size_t offset;
  };
  std::vector<Open> open;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '&') {
      std::size_t end = i + 1;
      if (auto p = check_reference(text, i, end)) return p;
      i = end;
      continue;
    }
    if (c == ']' && text.substr(i, 3) == "]]>") return XmlProblem{i, "']]>' is not allowed in text"};
    if (c != '<') {
      ++i;
      continue;
    }
    const std::string_view rest = text.substr(i);
    if (rest.substr(0, 4) == "<!--") {
      const std::size_t dashes = text.find("--", i + 4);
      if (dashes == std::string_view::npos) return XmlProblem{i, "the comment is not closed (no '-->')"};
      if (dashes + 2 >= text.size() || text[dashes + 2] != '>')
        return XmlProblem{dashes, "'--' is not allowed inside a comment"};
      i = dashes + 3;
      continue;
    }
    if (rest.substr(0, 9) == "<![CDATA[") {
      const std::size_t end = text.find("]]>", i + 9);
      if (end == std::string_view::npos) return XmlProblem{i, "the CDATA section is not closed (no ']]>')"};
      if (open.empty()) return XmlProblem{i, "a CDATA section outside the root element"};
      i = end + 3;
      continue;
    }
    if (rest.substr(0, 2) == "<!") {
      if (rest.substr(0, 9) == "<!DOCTYPE")
        return XmlProblem{i, "a DOCTYPE is not supported in rig definitions"};
      return XmlProblem{i, "unknown markup '<!'"};
    }
    if (rest.substr(0, 2) == "<?") {
      const std::size_t end = text.find("?>", i + 2);
      if (end == std::string_view::npos) return XmlProblem{i, "the processing instruction is not closed (no '?>')"};
      std::size_t k = i + 2;
      while (k < end && is_name_char(static_cast<unsigned char>(text[k]))) ++k;
      std::string target(text.substr(i + 2, k - i - 2));
      for (char& ch : target) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      if (target.empty()) return XmlProblem{i, "a processing instruction needs a target name"};
      if (target == "xml" && i != start)
        return XmlProblem{i, "the XML declaration must come first in the file"};
      i = end + 2;
      continue;
    }
    if (rest.substr(0, 2) == "</") {
      std::size_t k = i + 2;
      while (k < text.size() && is_name_char(static_cast<unsigned char>(text[k]))) ++k;
      const std::string_view name = text.substr(i + 2, k - i - 2);
      while (k < text.size() && is_space(text[k])) ++k;
      if (name.empty() || k >= text.size() || text[k] != '>') return XmlProblem{i, "malformed end tag"};
      if (open.empty()) return XmlProblem{i, "</" + std::string(name) + "> closes no element"};
      if (open.back().name != name)
        return XmlProblem{i + 2, "Start-end tags mismatch"};
      open.pop_back();
      i = k + 1;
      continue;
    }
    // A start tag.
    std::size_t k = i + 1;
    if (k >= text.size() || !is_name_start(static_cast<unsigned char>(text[k])))
      return XmlProblem{i, "'<' must start a tag (write &lt; for the character)"};
    while (k < text.size() && is_name_char(static_cast<unsigned char>(text[k]))) ++k;
    const std::string_view name = text.substr(i + 1, k - i - 1);
    bool closed = false;
    for (;;) {
      const std::size_t before_space = k;
      while (k < text.size() && is_space(text[k])) ++k;
      if (k >= text.size()) return XmlProblem{i, "<" + std::string(name) + "> is not closed (no '>')"};
      if (text[k] == '>') {
        ++k;
        break;
      }
      if (text.substr(k, 2) == "/>") {
        k += 2;
        closed = true;
        break;
      }
      if (k == before_space) return XmlProblem{k, "attributes must be separated by white space"};
      if (!is_name_start(static_cast<unsigned char>(text[k]))) return XmlProblem{k, "expected an attribute name"};
      const std::size_t attr = k;
      while (k < text.size() && is_name_char(static_cast<unsigned char>(text[k]))) ++k;
      while (k < text.size() && is_space(text[k])) ++k;
      if (k >= text.size() || text[k] != '=') return XmlProblem{attr, "an attribute needs '=' and a quoted value"};
      ++k;
      while (k < text.size() && is_space(text[k])) ++k;
      if (k >= text.size() || (text[k] != '"' && text[k] != '\''))
        return XmlProblem{attr, "an attribute value must be quoted"};
      const char quote = text[k++];
      while (k < text.size() && text[k] != quote) {
        if (text[k] == '<') return XmlProblem{k, "'<' is not allowed in an attribute value (write &lt;)"};
        if (text[k] == '&') {
          std::size_t end = k + 1;
          if (auto p = check_reference(text, k, end)) return p;
          k = end;
          continue;
        }
        ++k;
      }
      if (k >= text.size()) return XmlProblem{attr, "the attribute value is not closed"};
      ++k;
    }
    if (!closed) {
      if (open.size() >= kMaxTextDepth)
        return XmlProblem{i, "elements nest deeper than " + std::to_string(kMaxTextDepth) + " levels (the limit)"};
      open.push_back(Open{name, i});
    }
    i = k;
  }
  if (!open.empty()) return XmlProblem{open.back().offset, "<" + std::string(open.back().name) + "> is not closed"};
  return std::nullopt;
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
      } else if (name == "data") {
        d.data.push_back(read_data(c));
      } else if (name == "component") {
        d.components.push_back(read_component(c, 1));
      } else {
        unknown_element(n, c, {"geo", "feature", "data", "component"});
      }
    });
  }

  DataImport read_data(pugi::xml_node n) {
    DataImport x;
    x.where = at(n);
    check_attrs(n, {"kind", "file"});
    x.kind = n.attribute("kind").value();
    x.file = n.attribute("file").value();
    children(n, [&](pugi::xml_node c, std::string_view) { unknown_element(n, c, {}); });
    return x;
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

  Component read_component(pugi::xml_node n, std::size_t depth) {
    Component c;
    c.where = at(n);

    const auto attrs = check_attrs(n, {"type", "name", "side", "version", "rigId", "attach", "after", "guiLocation"});
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
    for (std::string_view id : split_words(n.attribute("after").value())) c.after.emplace_back(id);
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
        if (depth + 1 > kMaxComponentDepth)
          error(at(e), "components nest deeper than " + std::to_string(kMaxComponentDepth) + " levels (the limit)");
        else
          c.children.push_back(read_component(e, depth + 1));
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
    if (!c.after.empty()) attrs.emplace_back("after", join_words(c.after));
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
    const bool has_children = !d.geometry.empty() || !d.features.empty() || !d.data.empty() || !d.components.empty();
    open(0, "rig", attrs, has_children);
    for (const Geometry& g : d.geometry) {
      Attrs a = {{"file", g.file}};
      if (!g.name.empty()) a.emplace_back("name", g.name);
      open(1, "geo", a, false);
    }
    for (const Feature& f : d.features) feature(1, f);
    for (const DataImport& x : d.data) open(1, "data", {{"kind", x.kind}, {"file", x.file}}, false);
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
  {
    const LineIndex lines(text);
    if (std::optional<XmlProblem> p = check_well_formed(text)) {
      result.errors.push_back({source, lines.at(p->offset), "XML syntax error: " + p->message});
      *fatal = true;
      return result;
    }
  }
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
