// The JSON Schema (draft 2020-12) and the XSD (1.0) of the definition
// formats, generated from the component schemas. The shipped copies,
// schemas/rig.schema.json and schemas/rig.xsd, are this output
// (`rigel schema --json > schemas/rig.schema.json`, `rigel schema --xsd >
// schemas/rig.xsd`); a test keeps them equal.
//
// Both describe what validate() checks where their language can say it. The
// JSON Schema types every parameter by its component's type (if/then per
// type). XSD 1.0 cannot make an attribute's type depend on another
// attribute, so there a <param>'s value is text and the parameters of each
// type are listed in the documentation of the ComponentType enumeration;
// `rigel validate` checks them.
#include <nlohmann/json.hpp>

#include <iterator>
#include <set>

#include "definition_io_internal.h"
#include "rigel/scene/shapes.h"

namespace rigel::rig {

nlohmann::ordered_json detail::param_value_json(const ParamValue& v) {
  if (const auto* b = std::get_if<bool>(&v)) return *b;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return *i;
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* x = std::get_if<math::Vec3>(&v)) return nlohmann::ordered_json::array({x->x(), x->y(), x->z()});
  return std::get<std::string>(v);
}

namespace {

using Json = nlohmann::ordered_json;

// Text that from_chars reads as a finite double (no leading '+', no inf/nan).
constexpr const char* kNumberPattern = R"(-?(\d+\.?\d*|\.\d+)([eE][+\-]?\d+)?)";
constexpr const char* kNamePattern = "^[A-Za-z0-9_-]+$";
constexpr const char* kRigIdPattern =
    "^[0-9a-fA-F]{8}-?[0-9a-fA-F]{4}-?4[0-9a-fA-F]{3}-?[89abAB][0-9a-fA-F]{3}-?[0-9a-fA-F]{12}$";

Json strings(const std::vector<std::string>& items) {
  Json a = Json::array();
  for (const std::string& s : items) a.push_back(s);
  return a;
}

Json ref(const char* def) { return Json{{"$ref", std::string("#/$defs/") + def}}; }

Json array_of(const char* def) {
  Json j = Json::object();
  j["type"] = "array";
  j["items"] = ref(def);
  return j;
}

Json param_schema(const ParamSpec& p) {
  Json j = Json::object();
  switch (p.type) {
    case ParamType::kBool: j["type"] = "boolean"; break;
    case ParamType::kInt: j["type"] = "integer"; break;
    case ParamType::kDouble: j["type"] = "number"; break;
    case ParamType::kString: j["type"] = "string"; break;
    case ParamType::kEnum: j["enum"] = strings(p.choices); break;
    case ParamType::kVec3: j["$ref"] = "#/$defs/vec3"; break;
  }
  if (p.min) j["minimum"] = *p.min;
  if (p.max) j["maximum"] = *p.max;
  j["default"] = detail::param_value_json(p.default_value);
  j["description"] = p.help;
  return j;
}

// The part of a component's schema that depends on its type.
Json component_type_schema(const ComponentSchema& s) {
  Json j = Json::object();
  j["description"] = s.help;
  Json props = Json::object();
  {
    Json params = Json::object();
    params["type"] = "object";
    Json p = Json::object();
    for (const ParamSpec& spec : s.params) p[spec.name] = param_schema(spec);
    params["properties"] = std::move(p);
    params["additionalProperties"] = false;
    props["params"] = std::move(params);
  }
  {
    Json guides = Json::object();
    guides["description"] = s.guides.help;
    guides["minItems"] = s.guides.min;
    if (s.guides.max >= 0) guides["maxItems"] = s.guides.max;
    if (!s.guides.names.empty()) {
      Json prefix = Json::array();
      for (const std::string& n : s.guides.names) prefix.push_back(Json{{"properties", Json{{"name", Json{{"const", n}}}}}});
      guides["prefixItems"] = std::move(prefix);
    }
    props["guides"] = std::move(guides);
  }
  {
    Json controls = Json::object();
    std::vector<std::string> roles;
    for (const ControlSpec& c : s.controls) roles.push_back(c.role);
    if (roles.empty()) controls["maxItems"] = 0;
    else controls["items"] = Json{{"properties", Json{{"role", Json{{"enum", strings(roles)}}}}}};
    props["controls"] = std::move(controls);
  }
  {
    Json features = Json::object();
    if (s.features.empty()) features["maxItems"] = 0;
    else features["items"] = Json{{"properties", Json{{"name", Json{{"enum", strings(s.features)}}}}}};
    props["features"] = std::move(features);
  }
  j["properties"] = std::move(props);
  return j;
}

}  // namespace

// Over 150 lines: the JSON Schema document written top to bottom in the
// order it reads; split, its parts would be read out of order.
std::string definition_json_schema(const SchemaRegistry& schemas) {
  Json defs = Json::object();
  {
    Json v = Json::object();
    v["type"] = "array";
    v["items"] = Json{{"type", "number"}};
    v["minItems"] = 3;
    v["maxItems"] = 3;
    v["description"] = "[x, y, z]";
    defs["vec3"] = std::move(v);
    Json g = Json::object();
    g["type"] = "array";
    g["items"] = Json{{"type", "number"}};
    g["minItems"] = 2;
    g["maxItems"] = 2;
    g["description"] = "[x, y]: where the node editor draws the element.";
    defs["guiLocation"] = std::move(g);
  }
  defs["name"] = Json{{"type", "string"},
                      {"pattern", kNamePattern},
                      {"description", "Letters, digits, '_' and '-': names prefix node names."}};
  defs["rigId"] = Json{{"type", "string"},
                       {"pattern", kRigIdPattern},
                       {"description", "A UUID v4, with or without dashes: the component's identity across versions."}};
  defs["shape"] = Json{{"enum", strings(scene::control_shape_names())}};
  defs["color"] = Json{{"anyOf", Json::array({Json{{"enum", strings(scene::color_names())}},
                                               Json{{"type", "string"}, {"pattern", "^#[0-9a-fA-F]{6}$"}}})}};
  {
    Json sw = Json::object();
    sw["type"] = "object";
    sw["required"] = Json::array({"name"});
    sw["additionalProperties"] = false;
    sw["properties"] = Json{{"name", Json{{"type", "string"}, {"minLength", 1}}},
                            {"enabled", Json{{"type", "boolean"}, {"default", true}}}};
    defs["switch"] = std::move(sw);
    Json f = Json::object();
    f["type"] = "object";
    f["required"] = Json::array({"name"});
    f["additionalProperties"] = false;
    f["properties"] = Json{{"name", Json{{"type", "string"}, {"minLength", 1}}},
                           {"enabled", Json{{"type", "boolean"}, {"default", true}}},
                           {"switches", array_of("switch")}};
    defs["feature"] = std::move(f);
  }
  {
    Json g = Json::object();
    g["type"] = "object";
    g["required"] = Json::array({"file"});
    g["additionalProperties"] = false;
    g["properties"] = Json{{"file", Json{{"type", "string"}, {"minLength", 1}, {"description", "Character file, relative to the definition's folder."}}},
                           {"name", Json{{"type", "string"}, {"description", "A mesh in the file."}}}};
    defs["geometry"] = std::move(g);
  }
  {
    Json x = Json::object();
    x["type"] = "object";
    x["required"] = Json::array({"kind", "file"});
    x["additionalProperties"] = false;
    Json kinds = Json::array();
    for (const char* k : kDataImportKinds) kinds.push_back(k);
    x["properties"] = Json{{"kind", Json{{"enum", std::move(kinds)}}},
                           {"file", Json{{"type", "string"}, {"minLength", 1}, {"description", "Data file, relative to the definition's folder."}}}};
    x["description"] = "Hand-made data the build imports, in order, after the components are built (its last step, data).";
    defs["data"] = std::move(x);
  }
  {
    Json g = Json::object();
    g["type"] = "object";
    g["additionalProperties"] = false;
    g["properties"] = Json{{"name", Json{{"type", "string"}}},
                           {"joint", Json{{"type", "string"}, {"description", "Character joint giving the location at build time."}}},
                           {"translate", ref("vec3")},
                           {"rotate", ref("vec3")},
                           {"scale", ref("vec3")}};
    defs["guide"] = std::move(g);
  }
  {
    Json c = Json::object();
    c["type"] = "object";
    c["required"] = Json::array({"role"});
    c["additionalProperties"] = false;
    c["properties"] = Json{{"role", Json{{"type", "string"}}},
                           {"shape", ref("shape")},
                           {"color", ref("color")},
                           {"size", Json{{"type", "number"}, {"exclusiveMinimum", 0}, {"default", 1.0}}}};
    defs["control"] = std::move(c);
  }
  {
    Json c = Json::object();
    c["type"] = "object";
    c["required"] = Json::array({"type", "name", "rigId"});
    c["additionalProperties"] = false;
    Json props = Json::object();
    props["type"] = Json{{"enum", strings(schemas.types())}};
    props["name"] = ref("name");
    props["side"] = Json{{"enum", Json::array({"C", "L", "R"})}, {"default", "C"}};
    props["version"] = Json{{"type", "string"}, {"minLength", 1}, {"default", "1.0"}};
    props["rigId"] = ref("rigId");
    props["attach"] = Json{
        {"type", "string"},
        {"description",
         "A hook of the parent (name, index, START, MIDDLE, END; default hook 0), or OTHER.HOOK: a hook of another "
         "component, OTHER a name, NAME_SIDE or rigId."}};
    props["after"] = Json{{"type", "array"},
                          {"items", ref("rigId")},
                          {"description",
                           "rigIds of other components it builds after (what it reads from them); an update that "
                           "rebuilds one rebuilds it too."}};
    props["guiLocation"] = ref("guiLocation");
    props["guides"] = array_of("guide");
    props["controls"] = array_of("control");
    props["params"] = Json{{"type", "object"}};
    props["features"] = array_of("feature");
    props["children"] = array_of("component");
    c["properties"] = std::move(props);
    Json all = Json::array();
    for (const std::string& type : schemas.types()) {
      Json rule = Json::object();
      rule["if"] = Json{{"properties", Json{{"type", Json{{"const", type}}}}}, {"required", Json::array({"type"})}};
      rule["then"] = Json{{"$ref", "#/$defs/component." + type}};
      all.push_back(std::move(rule));
    }
    c["allOf"] = std::move(all);
    defs["component"] = std::move(c);
  }
  for (const std::string& type : schemas.types()) defs["component." + type] = component_type_schema(*schemas.find(type));
  {
    Json r = Json::object();
    r["type"] = "object";
    r["required"] = Json::array({"name"});
    r["additionalProperties"] = false;
    r["properties"] = Json{{"name", ref("name")},
                           {"version", Json{{"type", "string"}, {"minLength", 1}, {"default", "1.0"}}},
                           {"guiLocation", ref("guiLocation")},
                           {"geometry", array_of("geometry")},
                           {"features", array_of("feature")},
                           {"data", array_of("data")},
                           {"components", array_of("component")}};
    defs["rig"] = std::move(r);
  }
  Json root = Json::object();
  root["$schema"] = "https://json-schema.org/draft/2020-12/schema";
  root["title"] = "rigel rig definition (.rig.json)";
  root["description"] =
      "Generated by `rigel schema --json` from the component schemas; docs/RIG.md describes the format. "
      "`rigel validate` checks what a schema cannot: unique names and rigIds, hooks and cycles.";
  root["type"] = "object";
  root["required"] = Json::array({"rig"});
  root["additionalProperties"] = false;
  root["properties"] = Json{{"rig", ref("rig")}};
  root["$defs"] = std::move(defs);
  return root.dump(2) + "\n";
}

namespace {

std::string esc(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string join(const std::vector<std::string>& items, const char* separator) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : separator) + s;
  return out;
}

// One paragraph about a component type: help, parameters, guides, controls,
// hooks (the documentation of its ComponentType enumeration value).
std::string type_documentation(const ComponentSchema& s) {
  std::string out = s.help;
  if (s.params.empty()) {
    out += " Parameters: none.";
  } else {
    out += " Parameters:";
    for (const ParamSpec& p : s.params) {
      out += " " + p.name + " (" + param_type_name(p.type);
      if (!p.choices.empty()) {
        out += ' ';
        out += join(p.choices, "|");
      }
      if (p.min) {
        out += ", min ";
        out += detail::format_double(*p.min);
      }
      if (p.max) {
        out += ", max ";
        out += detail::format_double(*p.max);
      }
      out += ", default " + detail::param_text(p.default_value) + "): " + p.help;
    }
  }
  out += " Guides: " + std::to_string(s.guides.min) +
         (s.guides.max == s.guides.min ? "" : s.guides.max < 0 ? " or more" : " to " + std::to_string(s.guides.max));
  if (!s.guides.names.empty()) out += " (" + join(s.guides.names, ", ") + ")";
  out += ".";
  std::vector<std::string> roles;
  for (const ControlSpec& c : s.controls) roles.push_back(c.role);
  out += " Control roles: " + (roles.empty() ? std::string("none") : join(roles, ", ")) + ".";
  out += " Hooks: " + join(s.hooks, ", ") + ".";
  return out;
}

}  // namespace

constexpr const char* kDataDoc =
    "Hand-made data the build imports, in order, after the components are built (its last step, data); file is "
    "relative to the definition's folder.";

// Over 150 lines: the XSD document written top to bottom in the order it
// reads; split, its parts would be read out of order.
std::string definition_xsd(const SchemaRegistry& schemas) {
  const std::string num = kNumberPattern;
  std::string o;
  auto line = [&o](int depth, const std::string& text) {
    o.append(static_cast<std::size_t>(2 * depth), ' ');
    o += text;
    o += '\n';
  };
  auto enumeration = [&](const std::string& name, const std::vector<std::string>& values, const char* doc) {
    line(1, "<xs:simpleType name=\"" + name + "\">");
    if (doc) line(2, std::string("<xs:annotation><xs:documentation>") + esc(doc) + "</xs:documentation></xs:annotation>");
    line(2, "<xs:restriction base=\"xs:string\">");
    for (const std::string& v : values) line(3, "<xs:enumeration value=\"" + esc(v) + "\"/>");
    line(2, "</xs:restriction>");
    line(1, "</xs:simpleType>");
  };
  auto pattern = [&](const std::string& name, const std::string& regex, const char* doc) {
    line(1, "<xs:simpleType name=\"" + name + "\">");
    if (doc) line(2, std::string("<xs:annotation><xs:documentation>") + esc(doc) + "</xs:documentation></xs:annotation>");
    line(2, "<xs:restriction base=\"xs:string\"><xs:pattern value=\"" + esc(regex) + "\"/></xs:restriction>");
    line(1, "</xs:simpleType>");
  };
  auto attr = [&](int depth, const char* name, const char* type, const char* extra = "") {
    line(depth, std::string("<xs:attribute name=\"") + name + "\" type=\"" + type + "\"" + extra + "/>");
  };

  o += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  line(0, "<xs:schema xmlns:xs=\"http://www.w3.org/2001/XMLSchema\">");
  // Not an XML comment: comments may not hold "--".
  line(1, "<xs:annotation><xs:documentation>" +
              esc("rigel rig definition (.rig.xml), XSD 1.0. Generated by `rigel schema --xsd` from the component "
                  "schemas; docs/RIG.md describes the format. XSD 1.0 cannot type a <param> by its component's type: "
                  "each type's parameters are listed in the documentation of ComponentType below, and `rigel validate` "
                  "checks them, with names, rigIds, hooks and cycles.") +
              "</xs:documentation></xs:annotation>");
  line(1, "<xs:element name=\"rig\" type=\"Rig\"/>");

  line(1, "<xs:complexType name=\"Rig\">");
  line(2, "<xs:choice minOccurs=\"0\" maxOccurs=\"unbounded\">");
  line(3, "<xs:element name=\"geo\" type=\"Geo\"/>");
  line(3, "<xs:element name=\"feature\" type=\"Feature\"/>");
  line(3, "<xs:element name=\"data\" type=\"Data\"/>");
  line(3, "<xs:element name=\"component\" type=\"Component\"/>");
  line(2, "</xs:choice>");
  attr(2, "name", "Name", " use=\"required\"");
  attr(2, "version", "Version", " default=\"1.0\"");
  attr(2, "guiLocation", "GuiLocation");
  line(1, "</xs:complexType>");

  line(1, "<xs:complexType name=\"Geo\">");
  attr(2, "file", "NonEmpty", " use=\"required\"");
  attr(2, "name", "xs:string");
  line(1, "</xs:complexType>");

  line(1, "<xs:complexType name=\"Data\">");
  line(2, "<xs:annotation><xs:documentation>" + esc(kDataDoc) + "</xs:documentation></xs:annotation>");
  attr(2, "kind", "DataKind", " use=\"required\"");
  attr(2, "file", "NonEmpty", " use=\"required\"");
  line(1, "</xs:complexType>");

  line(1, "<xs:complexType name=\"Feature\">");
  line(2, "<xs:sequence><xs:element name=\"switch\" type=\"Switch\" minOccurs=\"0\" maxOccurs=\"unbounded\"/></xs:sequence>");
  attr(2, "name", "NonEmpty", " use=\"required\"");
  attr(2, "enabled", "Bool", " default=\"true\"");
  line(1, "</xs:complexType>");
  line(1, "<xs:complexType name=\"Switch\">");
  attr(2, "name", "NonEmpty", " use=\"required\"");
  attr(2, "enabled", "Bool", " default=\"true\"");
  line(1, "</xs:complexType>");

  line(1, "<xs:complexType name=\"Component\">");
  line(2, "<xs:choice minOccurs=\"0\" maxOccurs=\"unbounded\">");
  line(3, "<xs:element name=\"guide\" type=\"Guide\"/>");
  line(3, "<xs:element name=\"control\" type=\"Control\"/>");
  line(3, "<xs:element name=\"param\" type=\"Param\"/>");
  line(3, "<xs:element name=\"feature\" type=\"Feature\"/>");
  line(3, "<xs:element name=\"component\" type=\"Component\"/>");
  line(2, "</xs:choice>");
  attr(2, "type", "ComponentType", " use=\"required\"");
  attr(2, "name", "Name", " use=\"required\"");
  attr(2, "side", "Side", " default=\"C\"");
  attr(2, "version", "Version", " default=\"1.0\"");
  attr(2, "rigId", "RigId", " use=\"required\"");
  attr(2, "attach", "xs:string");
  attr(2, "after", "RigIdList");
  attr(2, "guiLocation", "GuiLocation");
  line(1, "</xs:complexType>");

  line(1, "<xs:complexType name=\"Guide\">");
  attr(2, "name", "xs:string");
  attr(2, "joint", "xs:string");
  attr(2, "translate", "Vec3", " default=\"0 0 0\"");
  attr(2, "rotate", "Vec3", " default=\"0 0 0\"");
  attr(2, "scale", "Vec3", " default=\"1 1 1\"");
  line(1, "</xs:complexType>");

  line(1, "<xs:complexType name=\"Control\">");
  attr(2, "role", "NonEmpty", " use=\"required\"");
  attr(2, "shape", "Shape");
  attr(2, "color", "Color");
  attr(2, "size", "Number", " default=\"1\"");
  line(1, "</xs:complexType>");

  line(1, "<xs:complexType name=\"Param\">");
  attr(2, "name", "ParamName", " use=\"required\"");
  attr(2, "value", "xs:string", " use=\"required\"");
  line(1, "</xs:complexType>");

  // Component types, each documented with its parameters.
  line(1, "<xs:simpleType name=\"ComponentType\">");
  line(2, "<xs:restriction base=\"xs:string\">");
  for (const std::string& type : schemas.types()) {
    line(3, "<xs:enumeration value=\"" + esc(type) + "\">");
    line(4, "<xs:annotation><xs:documentation>" + esc(type_documentation(*schemas.find(type))) +
                "</xs:documentation></xs:annotation>");
    line(3, "</xs:enumeration>");
  }
  line(2, "</xs:restriction>");
  line(1, "</xs:simpleType>");
  std::set<std::string> param_names;
  for (const std::string& type : schemas.types())
    for (const ParamSpec& p : schemas.find(type)->params) param_names.insert(p.name);
  enumeration("ParamName", std::vector<std::string>(param_names.begin(), param_names.end()),
              "Every parameter name of every component type; which ones a type takes is in ComponentType.");
  enumeration("Side", {"C", "L", "R"}, nullptr);
  enumeration("DataKind", std::vector<std::string>(std::begin(kDataImportKinds), std::end(kDataImportKinds)), nullptr);
  enumeration("Bool", {"true", "false"}, nullptr);
  enumeration("Shape", scene::control_shape_names(), nullptr);
  line(1, "<xs:simpleType name=\"Color\">");
  line(2, "<xs:union>");
  line(3, "<xs:simpleType>");
  line(4, "<xs:restriction base=\"xs:string\">");
  for (const std::string& c : scene::color_names()) line(5, "<xs:enumeration value=\"" + esc(c) + "\"/>");
  line(4, "</xs:restriction>");
  line(3, "</xs:simpleType>");
  line(3, "<xs:simpleType><xs:restriction base=\"xs:string\"><xs:pattern value=\"#[0-9a-fA-F]{6}\"/></xs:restriction></xs:simpleType>");
  line(2, "</xs:union>");
  line(1, "</xs:simpleType>");
  pattern("Name", "[A-Za-z0-9_\\-]+", "Letters, digits, '_' and '-': names prefix node names.");
  pattern("NonEmpty", ".+", nullptr);
  pattern("Version", ".+", nullptr);
  pattern("RigId", "[0-9a-fA-F]{8}-?[0-9a-fA-F]{4}-?4[0-9a-fA-F]{3}-?[89abAB][0-9a-fA-F]{3}-?[0-9a-fA-F]{12}",
          "A UUID v4, with or without dashes.");
  line(1, "<xs:simpleType name=\"RigIdList\">");
  line(2, "<xs:annotation><xs:documentation>rigIds separated by spaces.</xs:documentation></xs:annotation>");
  line(2, "<xs:list itemType=\"RigId\"/>");
  line(1, "</xs:simpleType>");
  pattern("Number", num, nullptr);
  pattern("Vec3", "\\s*" + num + "\\s+" + num + "\\s+" + num + "\\s*", "Three numbers: x y z.");
  pattern("GuiLocation", "\\s*" + num + "\\s*,\\s*" + num + "\\s*", "x,y: where the node editor draws the element.");
  line(0, "</xs:schema>");
  return o;
}

}  // namespace rigel::rig
