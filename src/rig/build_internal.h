#pragma once
// What the build's sources share (build.cc, build_steps.cc, build_records.cc,
// build_rebuild.cc, build_edit.cc, build_context.cc): the step records and
// the recorder that makes them, Build's records of what it did, and a few
// helpers on guides and controls. Not a public header.

#include <map>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/rig/build.h"
#include "rigel/rig/definition.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace detail {

using Json = nlohmann::ordered_json;
// Names every build source uses (they say `using namespace detail;`).
using graph::Plug;
using graph::Value;
using math::Mat4;
namespace xform = scene::xform;

// The names of the steps a build adds itself: the rig's own step (its
// metaRoot and groups) and each component's first step (its metaComponent).
inline constexpr const char* kRigStep = "rig";
inline constexpr const char* kMetaStep = "meta";
// The rig's last step when its definition names data (Definition::data):
// each entry imported by the factory's data importer.
inline constexpr const char* kDataStep = "data";

// A guide's values as a matrix: its place, or its offset from its joint.
math::Mat4 guide_values(const Guide& guide);

// ---- what a step did (build_records.cc) ------------------------------------

// A plug by node uuid and attribute name, so a record outlives the process.
struct PlugRef {
  graph::Uuid node;
  std::string attr;
  int element = -1;
};

struct ValueChange {
  PlugRef plug;
  graph::Value before;
};

struct ConnectionChange {
  PlugRef src, dst;
};

// What one step's construct did: the nodes it made, and what it changed on
// nodes it did not make (values as they were, connections made and broken,
// names as they were).
struct StepRecord {
  std::string step;
  std::vector<graph::Uuid> created;
  std::vector<ValueChange> values;
  std::vector<ConnectionChange> made, broken;
  std::vector<std::pair<graph::Uuid, std::string>> renamed;
};

// A record as the JSON kept in a meta node's `buildRecord`, and back.
Json record_json(const graph::Graph& g, const StepRecord& r);
Result<StepRecord> record_from_json(const graph::Graph& g, const Json& j);

// Watches the graph while a construct runs. Nodes made by this step are its
// own; everything it does to other nodes is remembered with how it was.
class Recorder : public graph::Observer {
 public:
  Recorder(graph::Graph& g, StepRecord& record);
  ~Recorder() override;
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Why the step may not do what it did (deleting or tagging a node it did
  // not make); empty when it may.
  const std::string& failure() const { return failure_; }

  void node_added(const graph::Graph& g, NodeId id) override;
  void node_removed(const graph::Graph& g, NodeId id) override;
  void node_renamed(const graph::Graph& g, NodeId id, const std::string& old_name) override;
  void attribute_set(const graph::Graph& g, const graph::Plug& plug, const graph::Value& before) override;
  void connection_made(const graph::Graph& g, const graph::Connection& c) override;
  void connection_broken(const graph::Graph& g, const graph::Connection& c) override;
  void tag_changed(const graph::Graph& g, NodeId id, const std::string& key) override;

 private:
  void remember_value(const graph::Graph& g, const graph::Plug& plug, const graph::Value& before);

  graph::Graph& graph_;
  StepRecord& record_;
  std::unordered_set<graph::Uuid, graph::UuidHash> own_;
  std::string failure_;
};

// Undoes what a step did, newest first.
Status undo_record(graph::Graph& g, const StepRecord& r);

// ---- the plan ---------------------------------------------------------------

// Where a component attaches: (component index or -1 for the rig, hook reference).
struct AttachTarget {
  int component = -1;
  std::string hook;
};

// The owner of a planned step's records: the component's rigId, "" for the rig.
std::string key_of(const Build& b, int component);

// The data step's construct: each of `d.data` imported in order by the
// factory's importer onto the rig `root`; an entry's failure names the
// definition file:line and the data file (build_steps.cc).
Status import_definition_data(scene::Scene& scene, const Definition& d, const ComponentFactory& factory, NodeId root);

// ---- controls (build_rebuild.cc) ------------------------------------------

bool is_control(const graph::Graph& g, NodeId id);
// Puts a free channel of `control` at its rest value (inside a transaction).
Status zero_channels(graph::Graph& g, NodeId control);

}  // namespace detail

// What a Build did, as read from (and written to) the scene's meta nodes.
struct Build::Records {
  // (rigId or "" for the rig, step) -> what the step did
  std::map<std::pair<std::string, std::string>, detail::StepRecord> done;
  // owner -> the buildRecord text its entries in `done` were read from or
  // written as: sync() re-parses an owner only when the scene's text differs
  // (parsing every record on every step made builds quadratic).
  std::map<std::string, std::string> text;
  void forget(const std::string& owner) {
    text.erase(owner);
    for (auto it = done.begin(); it != done.end();) it = it->first.first == owner ? done.erase(it) : std::next(it);
  }
  std::vector<int> parent;                   // per component: index of its nesting parent, -1 for roots
  std::vector<detail::AttachTarget> attach;  // per component
  std::vector<std::vector<int>> after;      // per component: the indices of its Component::after
};

}  // namespace rigel::rig
