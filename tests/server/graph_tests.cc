// The build-graph routes (editor_routes.h): the web app's graph editor's
// palette, validation with problems placed on nodes and sockets, live
// builds that rebuild only what changed, saving and opening graph files
// under the root, and the refusals of bad requests.

#include <set>

#include "rigel/app/graphs.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"
#include "rigel/tools/build_functions.h"
#include "server_test_util.h"

namespace rigel::server {
namespace {

// The graph of two_component_definition(), as the editor sends it.
Json two_component_graph() {
  const std::string text = two_component_definition().dump(2);
  rig::ParseResult p = rig::parse_definition(text, rig::Syntax::kJson, "two.rig.json");
  EXPECT_TRUE(p.ok());
  return Json::parse(rig::write_build_graph(rig::convert_definition(p.definition)));
}

Json& node(Json& graph, const std::string& id) {
  for (Json& n : graph["buildGraph"]["nodes"])
    if (n["id"] == id) return n;
  ADD_FAILURE() << "no node " << id;
  static Json none;
  return none;
}

std::string uuid_of(const graph::Graph& g, graph::NodeId id) { return g.node(id)->uuid().str(); }

// The uuids of every node the rig's metadata network links to.
std::set<std::string> rig_node_uuids(const graph::Graph& g, const std::string& rig) {
  std::set<std::string> out;
  const graph::NodeId r = rig::find_rig(g, rig);
  for (graph::NodeId c : rig::rig_components(g, r))
    for (graph::NodeId m : rig::meta_members(g, c)) out.insert(uuid_of(g, m));
  return out;
}

TEST(ServerGraph, PaletteListsEveryKindWithTypesAndDefaults) {
  tools::register_build_functions();
  Served s = served_character();
  const Json p = s.get("/api/graph/palette");
  std::map<std::string, Json> kinds;
  for (const Json& k : p["kinds"]) kinds[k["id"]] = k;
  for (const char* id : {"start", "component:global", "component:limb", "constant:number", "variable:get", "variable:set",
                         "branch", "function:rigel.mirrorControlShapes"})
    EXPECT_TRUE(kinds.count(id)) << id;
  // A component parameter's default is its schema's.
  const rig::ComponentSchema* limb = s.workspace->workspace().factory().schemas().find("limb");
  ASSERT_NE(limb, nullptr);
  bool seen = false;
  for (const Json& in : kinds["component:limb"]["inputs"])
    if (in["name"] == limb->params.front().name) {
      seen = true;
      EXPECT_TRUE(in.contains("default")) << in;
    } else if (in["type"] == "exec" || in["type"] == "component") {
      EXPECT_FALSE(in.contains("default")) << in;
    }
  EXPECT_TRUE(seen);
  // A function input's default is the function's.
  for (const Json& in : kinds["function:rigel.setControlColor"]["inputs"]) {
    if (in["name"] == "color") {
      EXPECT_EQ(in["default"], Json::array({1.0, 1.0, 0.0})) << in;
    }
  }
  std::set<std::string> types;
  for (const Json& t : p["types"]) {
    types.insert(t["name"]);
    EXPECT_EQ(t["color"].get<std::string>().size(), 7u) << t;
  }
  EXPECT_TRUE(types.count("exec") && types.count("component") && types.count("number"));
}

TEST(ServerGraph, ProblemsNameTheirNodeAndSocket) {
  Served s = served_character();
  Json g = two_component_graph();
  Json v = s.post("/api/graph/validate", {{"graph", g}});
  EXPECT_TRUE(v["ok"].get<bool>()) << v;
  EXPECT_EQ(v["order"], Json::array({"global", "arm_L"}));
  EXPECT_EQ(v["rigIds"]["7c2d4b9e-3f1a-4e6b-8d0c-5a9b2e1f3c02"], "arm_L");

  // A wrong-typed link: named on the input's node and socket.
  Json typed = g;
  typed["buildGraph"]["links"].push_back({{"from", "global.component"}, {"to", "arm_L.name"}});
  v = s.post("/api/graph/validate", {{"graph", typed}});
  ASSERT_FALSE(v["ok"].get<bool>());
  EXPECT_EQ(v["problems"][0]["node"], "arm_L") << v;
  EXPECT_EQ(v["problems"][0]["socket"], "name") << v;

  // A node the exec chain never reaches.
  Json off = g;
  Json& links = off["buildGraph"]["links"];
  for (std::size_t i = 0; i < links.size(); ++i)
    if (links[i]["to"] == "arm_L.exec") links.erase(i--);
  v = s.post("/api/graph/validate", {{"graph", off}});
  ASSERT_FALSE(v["ok"].get<bool>());
  EXPECT_EQ(v["problems"][0]["node"], "arm_L") << v;
  EXPECT_NE(v["problems"][0]["message"].get<std::string>().find("exec chain"), std::string::npos) << v;

  // What validate() finds in a component: placed on its node, at the parameter.
  Json param = g;
  node(param, "arm_L")["component"]["params"] = {{"noSuchParam", 1}};
  v = s.post("/api/graph/validate", {{"graph", param}});
  ASSERT_FALSE(v["ok"].get<bool>());
  EXPECT_EQ(v["problems"][0]["node"], "arm_L") << v;
  EXPECT_EQ(v["problems"][0]["socket"], "noSuchParam") << v;

  // An unknown kind.
  Json unknown = g;
  node(unknown, "arm_L")["kind"] = "component:tentacle";
  v = s.post("/api/graph/validate", {{"graph", unknown}});
  ASSERT_FALSE(v["ok"].get<bool>());
  EXPECT_EQ(v["problems"][0]["node"], "arm_L") << v;
}

TEST(ServerGraph, BuildsLiveAndRebuildsOnlyWhatChanged) {
  tools::register_build_functions();
  Served s = served_character();
  const std::string character = io::write_scene(s.workspace->workspace().scene());
  Json g = two_component_graph();
  // A function node reading the arm: rebuilt with it, not with the global.
  g["buildGraph"]["nodes"].push_back({{"id", "colour"}, {"kind", "function:rigel.setControlColor"}});
  g["buildGraph"]["links"].push_back({{"from", "arm_L.then"}, {"to", "colour.exec"}});
  g["buildGraph"]["links"].push_back({{"from", "arm_L.component"}, {"to", "colour.component"}});
  Json built = s.post("/api/graph/build", {{"graph", g}});
  EXPECT_EQ(built["rig"], "arm");
  EXPECT_EQ(built["rebuilt"].size(), 3u) << built;
  EXPECT_EQ(built["rigIds"]["7c2d4b9e-3f1a-4e6b-8d0c-5a9b2e1f3c02"], "arm_L");
  const graph::Graph& graph = s.workspace->workspace().graph();
  const std::string global_id = "0b9f1e36-5a1e-4d8c-9a55-2f3c1d7e8a01";
  std::set<std::string> global_nodes;
  for (graph::NodeId m : rig::meta_members(graph, rig::find_component(graph, rig::find_rig(graph, "arm"), global_id)))
    global_nodes.insert(uuid_of(graph, m));
  ASSERT_FALSE(global_nodes.empty());

  // The arm's control size changes: the arm and the call reading it are
  // rebuilt; the global keeps its nodes (same uuids).
  node(g, "arm_L")["component"]["controls"][0]["size"] = 0.2;
  built = s.post("/api/graph/build", {{"graph", g}});
  EXPECT_EQ(built["rebuilt"].size(), 2u) << built;
  for (const Json& id : built["rebuilt"]) EXPECT_NE(id, global_id);
  std::set<std::string> after;
  for (graph::NodeId m : rig::meta_members(graph, rig::find_component(graph, rig::find_rig(graph, "arm"), global_id)))
    after.insert(uuid_of(graph, m));
  EXPECT_EQ(after, global_nodes);

  // A graph that does not compile: refused, the scene as it was.
  const std::set<std::string> nodes_before = rig_node_uuids(graph, "arm");
  Json bad = g;
  bad["buildGraph"]["links"].push_back({{"from", "global.component"}, {"to", "arm_L.name"}});
  const Response r = s.request("POST", "/api/graph/build", Json{{"graph", bad}}.dump());
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_NE(r.body.find("arm_L.name"), std::string::npos) << r.body;
  EXPECT_EQ(rig_node_uuids(graph, "arm"), nodes_before);

  // A step names its component's rigId, so the editor marks its node:
  // every step stands on one of the graph's components; from 0, the first
  // component step is the global's; the last is the call's (built last).
  const Json back = s.post("/api/rigs/step", {{"rig", "arm"}, {"by", -1}});
  std::set<std::string> ids;
  for (const auto& [rig_id, node_id] : built["rigIds"].items()) ids.insert(rig_id);
  EXPECT_TRUE(ids.count(back["rigId"].get<std::string>())) << back;
  EXPECT_EQ(s.post("/api/rigs/step", {{"rig", "arm"}, {"to", 0}})["rigId"], "");
  std::string first;
  for (int i = 0; i < 3 && first.empty(); ++i) first = s.post("/api/rigs/step", {{"rig", "arm"}, {"by", 1}})["rigId"];
  EXPECT_EQ(first, global_id);
  const Json end = s.post("/api/rigs/step", {{"rig", "arm"}, {"to", back["steps"]}});
  EXPECT_EQ(built["rigIds"][end["rigId"].get<std::string>()], "colour") << end;

  // Stepping the graph-built rig back to 0 and removing it give the character back.
  s.post("/api/rigs/remove", {{"rig", "arm"}});
  EXPECT_EQ(io::write_scene(s.workspace->workspace().scene()), character);
}

TEST(ServerGraph, SavesOpensAndListsGraphFilesUnderTheRoot) {
  Served s = served_character();
  Json g = two_component_graph();
  Json saved = s.post("/api/graph/save", {{"graph", g}, {"path", "graphs/arm.build.json"}});
  EXPECT_EQ(saved["version"], "1.0");
  EXPECT_TRUE(saved["problems"].empty());
  EXPECT_TRUE(rig::check_build_graph(s.root / "graphs/arm.build.json").ok());
  // The same content keeps the version; another bumps it.
  saved = s.post("/api/graph/save", {{"graph", g}, {"path", "graphs/arm.build.json"}});
  EXPECT_EQ(saved["version"], "1.0");
  node(g, "arm_L")["position"] = {400, 120};
  saved = s.post("/api/graph/save", {{"graph", g}, {"path", "graphs/arm.build.json"}});
  EXPECT_EQ(saved["version"], "1.1");
  // A graph being drawn is saved with its problems.
  Json wip = g;
  wip["buildGraph"]["nodes"].push_back({{"id", "loose"}, {"kind", "component:fkChain"}, {"component", {{"name", "loose"}}}});
  saved = s.post("/api/graph/save", {{"graph", wip}, {"path", "wip.build.json"}});
  ASSERT_FALSE(saved["problems"].empty());
  EXPECT_EQ(saved["problems"][0]["node"], "loose");

  EXPECT_EQ(s.get("/api/graph/files")["files"], Json::array({"graphs/arm.build.json", "wip.build.json"}));
  const Json opened = s.get("/api/graph?path=graphs/arm.build.json");
  EXPECT_EQ(opened["graph"]["buildGraph"]["rig"]["version"], "1.1");
  EXPECT_EQ(node(const_cast<Json&>(opened["graph"]), "arm_L")["position"], Json::array({400.0, 120.0}));

  // A rig built from a graph file opens as that file; one built from a
  // definition opens converted.
  s.post("/api/rigs/add", {{"definition", "graphs/arm.build.json"}});
  Json from_rig = s.get("/api/graph?rig=arm");
  EXPECT_FALSE(from_rig["converted"].get<bool>());
  EXPECT_EQ(from_rig["path"], "graphs/arm.build.json");
  s.post("/api/rigs/remove", {{"rig", "arm"}});
  s.post("/api/definition/build", {{"definition", two_component_definition()}});
  from_rig = s.get("/api/graph?rig=arm");
  EXPECT_TRUE(from_rig["converted"].get<bool>());
  EXPECT_EQ(from_rig["path"], "");
  EXPECT_EQ(node(from_rig["graph"], "arm_L")["component"]["rigId"], "7c2d4b9e-3f1a-4e6b-8d0c-5a9b2e1f3c02");
}

TEST(ServerGraph, RefusesBadRequests) {
  Served s = served_character();
  const Json g = two_component_graph();
  const auto status = [&](const std::string& method, const std::string& target, const Json& body) {
    return s.request(method, target, method == "GET" ? "" : body.dump()).status;
  };
  EXPECT_EQ(status("POST", "/api/graph/validate", Json::object()), 400);
  EXPECT_EQ(status("POST", "/api/graph/validate", {{"graph", "text"}}), 400);
  EXPECT_EQ(status("POST", "/api/graph/build", {{"graph", {{"buildGraph", {{"format", 99}}}}}}), 400);
  EXPECT_EQ(status("POST", "/api/graph/save", {{"graph", g}, {"path", "../out.build.json"}}), 400);
  EXPECT_EQ(status("POST", "/api/graph/save", {{"graph", g}, {"path", "/tmp/out.build.json"}}), 400);
  EXPECT_EQ(status("POST", "/api/graph/save", {{"graph", g}, {"path", "arm.rig.json"}}), 400);
  EXPECT_FALSE(fs::exists(s.root / "arm.rig.json"));
  EXPECT_EQ(status("GET", "/api/graph?path=missing.build.json", {}), 404);
  EXPECT_EQ(status("GET", "/api/graph?path=../x.build.json", {}), 400);
  EXPECT_EQ(status("GET", "/api/graph?path=a.rig.xml", {}), 400);
  EXPECT_EQ(status("GET", "/api/graph", {}), 400);
  EXPECT_EQ(status("GET", "/api/graph?rig=none", {}), 404);
  write_text(s.root / "broken.build.json", "{\"buildGraph\": {\"format\": 1, \"nodes\": [}");
  const Response r = s.request("GET", "/api/graph?path=broken.build.json", "");
  EXPECT_EQ(r.status, 400);
  EXPECT_NE(r.body.find("broken.build.json:1:"), std::string::npos) << r.body;
}

}  // namespace
}  // namespace rigel::server
