// The build functions rigel ships (build_functions.h).
#include "rigel/tools/build_functions.h"

#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "rigel/rig/meta.h"
#include "rigel/rig/schema.h"
#include "rigel/rig/spaces.h"
#include "rigel/tools/rigging.h"

namespace rigel::tools {
namespace {

using graph::NodeId;

std::string name_of(const graph::Graph& g, NodeId meta) {
  return rig::meta_string(g, meta, "componentName");
}

// The controls the `component` input's component made (an error when none).
Result<std::vector<NodeId>> component_controls(rig::FunctionCall& call) {
  const graph::Graph& g = call.scene().graph();
  const NodeId meta = call.component("component");
  std::vector<NodeId> controls = rig::meta_controls(g, meta);
  if (controls.empty())
    return error(ErrorCode::kInvalidArgument, "component '" + name_of(g, meta) + "' has no controls");
  return controls;
}

Status mirror_control_shapes(rig::FunctionCall& call) {
  auto controls = component_controls(call);
  if (!controls) return controls.status();
  auto mirrored = mirror_shape_to_opposite(call.scene(), *controls);
  if (!mirrored) return mirrored.status();
  call.set_output("count", static_cast<std::int64_t>(mirrored->size()));
  return Status::ok();
}

Status set_control_color(rig::FunctionCall& call) {
  auto controls = component_controls(call);
  if (!controls) return controls.status();
  ControlLook look;
  look.color = std::get<math::Vec3>(*call.value("color"));
  if (Status s = paste_control_look(call.scene().graph(), *controls, look, LookParts{.shape = false, .color = true}); !s)
    return s;
  call.set_output("count", static_cast<std::int64_t>(controls->size()));
  return Status::ok();
}

Status add_space_to(rig::FunctionCall& call) {
  graph::Graph& g = call.scene().graph();
  const NodeId meta = call.component("component");
  const std::string role = std::get<std::string>(*call.value("control"));
  const auto index = std::get<std::int64_t>(*call.value("index"));
  Result<NodeId> control = rig::get_meta_connection(g, meta, role, static_cast<int>(index));
  if (!control)
    return error(ErrorCode::kNotFound, "component '" + name_of(g, meta) + "' has no control '" + role + "' [" +
                                           std::to_string(index) + "]");
  // The target: the hook of the target component, by name or index, as
  // the build resolves an attach.
  const NodeId target_meta = call.component("target");
  const std::string hook = std::get<std::string>(*call.value("hook"));
  const rig::Component* target_def = call.component_definition("target");
  const rig::ComponentSchema* schema = target_def ? rig::builtin_schemas().find(target_def->type) : nullptr;
  const std::optional<int> k = schema ? rig::resolve_hook(schema->hook_names(*target_def), hook) : std::nullopt;
  NodeId target;
  for (NodeId m : rig::meta_members(g, target_meta)) {
    const std::string* h = g.node(m)->tag_find(rig::kTagHook);
    if (h && k && *h == std::to_string(*k)) target = m;
  }
  if (!target.is_valid())
    return error(ErrorCode::kNotFound, "component '" + name_of(g, target_meta) + "' publishes no hook '" + hook + "'");
  auto space = rig::add_space(call.scene(), *control, std::get<std::string>(*call.value("name")), target);
  if (!space) return space.status();
  call.set_output("space", static_cast<std::int64_t>(*space));
  return Status::ok();
}

// Pure: a + separator + b.
Status join_text(rig::FunctionCall& call) {
  const auto text = [&](const char* input) { return std::get<std::string>(*call.value(input)); };
  call.set_output("text", text("a") + text("separator") + text("b"));
  return Status::ok();
}

// Pure: an int as text, zero-padded to `digits`.
Status int_text(rig::FunctionCall& call) {
  const auto value = std::get<std::int64_t>(*call.value("value"));
  const auto digits = std::get<std::int64_t>(*call.value("digits"));
  if (digits < 0 || digits > 32) return error(ErrorCode::kInvalidArgument, "digits: " + std::to_string(digits) + " is not 0 to 32");
  // The magnitude in unsigned arithmetic: -INT64_MIN does not fit an int64.
  const std::uint64_t magnitude = value < 0 ? 0 - static_cast<std::uint64_t>(value) : static_cast<std::uint64_t>(value);
  std::string text = std::to_string(magnitude);
  if (text.size() < static_cast<std::size_t>(digits)) text.insert(0, static_cast<std::size_t>(digits) - text.size(), '0');
  call.set_output("text", (value < 0 ? "-" : "") + text);
  return Status::ok();
}

// Pure: the ints start, start + step, ... , count of them (a for-each's
// list: one finger per index).
Status int_range(rig::FunctionCall& call) {
  const auto count = std::get<std::int64_t>(*call.value("count"));
  const auto start = std::get<std::int64_t>(*call.value("start"));
  const auto step = std::get<std::int64_t>(*call.value("step"));
  // A loop's items: more than a graph may make is refused here, not built.
  constexpr std::int64_t kMost = 10000;
  if (count < 0 || count > kMost)
    return error(ErrorCode::kInvalidArgument, "count: " + std::to_string(count) + " is not 0 to " + std::to_string(kMost));
  const auto fits = [](std::int64_t v) { return v > -(std::int64_t{1} << 52) && v < (std::int64_t{1} << 52); };
  if (!fits(start) || !fits(step)) return error(ErrorCode::kInvalidArgument, "start and step must lie within +-2^52");
  rig::ValueList items;
  items.reserve(static_cast<std::size_t>(count));
  for (std::int64_t i = 0; i < count; ++i) items.push_back(start + i * step);
  call.set_list_output("items", std::move(items));
  return Status::ok();
}

// Pure: a text split at each separator ("thumb,index,middle" -> three).
Status split_text(rig::FunctionCall& call) {
  const auto text = std::get<std::string>(*call.value("text"));
  const auto separator = std::get<std::string>(*call.value("separator"));
  if (separator.empty()) return error(ErrorCode::kInvalidArgument, "separator: empty (it splits at each one)");
  rig::ValueList items;
  std::size_t from = 0;
  if (!text.empty())
    for (;;) {
      const std::size_t at = text.find(separator, from);
      items.push_back(text.substr(from, at == std::string::npos ? std::string::npos : at - from));
      if (at == std::string::npos) break;
      from = at + separator.size();
    }
  call.set_list_output("items", std::move(items));
  return Status::ok();
}

}  // namespace

Status add_build_functions(rig::FunctionRegistry& registry) {
  const auto add = [&](rig::BuildFunction f) {
    f.origin = "rigel";
    return registry.add(std::move(f));
  };
  Status s = add({"rigel.mirrorControlShapes",
                  "Mirror control shapes",
                  "Controls",
                  "Each control's shape onto its opposite control (the other side's), mirrored in the world.",
                  {{"component", "component", "the component whose shapes are copied"}},
                  {{"count", "int", "how many controls took a shape"}},
                  {},
                  mirror_control_shapes,
                  {}});
  if (s)
    s = add({"rigel.setControlColor",
             "Set control colour",
             "Controls",
             "Every control of a component takes a colour (linear RGB, 0 to 1).",
             {{"component", "component", "whose controls"}, {"color", "vector", "linear RGB, each 0 to 1"}},
             {{"count", "int", "how many controls"}},
             {rig::Param{"color", math::Vec3(1, 1, 0), {}}},
             set_control_color,
             {}});
  if (s)
    s = add({"rigel.addSpace",
             "Add space",
             "Spaces",
             "A control of a component gets a space that follows a hook of another component.",
             {{"component", "component", "whose control"},
              {"control", "string", "the control's role (ik, fk, main, ...)"},
              {"index", "int", "the control's index in its role"},
              {"name", "string", "the space's name"},
              {"target", "component", "the component it follows"},
              {"hook", "string", "the target's hook, by name or index"}},
             {{"space", "int", "the space's index"}},
             {rig::Param{"control", std::string("ik"), {}}, rig::Param{"hook", std::string("0"), {}}},
             add_space_to,
             {}});
  // Pure functions: values made while the graph compiles (names in loops).
  const auto pure = [&](rig::BuildFunction f) {
    f.pure = true;
    return add(std::move(f));
  };
  if (s)
    s = pure({"rigel.joinText",
              "Join text",
              "Values",
              "Two texts joined, with a separator between them: a name from a loop's element.",
              {{"a", "string", "the first text"}, {"b", "string", "the second text"}, {"separator", "string", "between them"}},
              {{"text", "string", "a, separator, b"}},
              {},
              join_text,
              {}});
  if (s)
    s = pure({"rigel.intText",
              "Number as text",
              "Values",
              "An int as text, zero-padded: a loop's index in a name (finger_01).",
              {{"value", "int", "the number"}, {"digits", "int", "pad with zeros to this many digits (0: none)"}},
              {{"text", "string", "the number's digits"}},
              {},
              int_text,
              {}});
  if (s)
    s = pure({"rigel.range",
              "Range",
              "Values",
              "count ints from start by step: the list a for-each runs over to make N of something.",
              {{"count", "int", "how many (0 to 10,000)"}, {"start", "int", "the first"}, {"step", "int", "between two"}},
              {{"items", "list:int", "start, start + step, ..."}},
              {rig::Param{"count", std::int64_t{3}, {}}, rig::Param{"step", std::int64_t{1}, {}}},
              int_range,
              {}});
  if (s)
    s = pure({"rigel.splitText",
              "Split text",
              "Values",
              "A text split at each separator: \"thumb,index,middle\" gives three names to loop over.",
              {{"text", "string", "the text"}, {"separator", "string", "where it is cut"}},
              {{"items", "list:string", "the parts, in order (none for an empty text)"}},
              {rig::Param{"separator", std::string(","), {}}},
              split_text,
              {}});
  return s;
}

Status add_flow_kinds(rig::FlowKindRegistry& registry) {
  rig::FlowKind sequence;
  sequence.id = "rigel.sequence";
  sequence.nice_name = "Sequence";
  sequence.help = "Runs what follows first, then second, then third (each to its chain's end): one build in "
                  "parts, each part reading what the earlier ones made.";
  sequence.exits = {"first", "second", "third"};
  sequence.run = [](rig::FlowCall& call) {
    for (const char* exit : {"first", "second", "third"}) call.go(exit);
    return Status::ok();
  };
  sequence.origin = "rigel";
  Status s = registry.add(std::move(sequence));
  if (!s) return s;
  rig::FlowKind repeat;
  repeat.id = "rigel.repeat";
  repeat.nice_name = "Repeat";
  repeat.help = "Runs its body count times, index 0 to count - 1 (a component node in it builds one component per "
                "pass: give each its own name from the index), then goes on through completed.";
  repeat.inputs = {{"count", "int", "how many passes (0 to 10,000)"}};
  repeat.outputs = {{"index", "int", "the pass, from 0"}};
  repeat.exits = {"body", "completed"};
  repeat.repeats = {"body"};
  repeat.defaults = {rig::Param{"count", std::int64_t{2}, {}}};
  repeat.run = [](rig::FlowCall& call) {
    const auto count = std::get<std::int64_t>(*call.value("count"));
    if (count < 0 || count > 10000)
      return error(ErrorCode::kInvalidArgument, "count: " + std::to_string(count) + " is not 0 to 10,000");
    for (std::int64_t i = 0; i < count; ++i) call.go("body", {{{"index", i}}, {}});
    call.go("completed");
    return Status::ok();
  };
  repeat.origin = "rigel";
  return registry.add(std::move(repeat));
}

void register_build_functions() {
  static std::once_flag once;
  std::call_once(once, [] {
    Status s = add_build_functions(rig::build_functions());
    if (s) s = add_flow_kinds(rig::flow_kinds());
    if (!s) {
      std::fprintf(stderr, "rigel: built-in build functions: %s\n", s.message().c_str());
      std::abort();
    }
  });
}

}  // namespace rigel::tools
