#include "rigel/ops/anim/clips.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>

namespace rigel::ops::anim {
namespace {

using graph::AttrSpec;
using graph::AttrType;
using graph::ComputeContext;
using graph::ValueType;

std::string index_name(const char* array, std::size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

// The clip list checked: equal lengths, unique non-empty names, finite
// times with start <= end.
Result<std::vector<Clip>> check_clips(const std::vector<std::string>& names, const std::vector<double>& starts,
                                      const std::vector<double>& ends) {
  namespace a = clips_attr;
  if (starts.size() != names.size() || ends.size() != names.size()) {
    return error(ErrorCode::kInvalidArgument, "clipNames: " + std::to_string(names.size()) + " names for " +
                                                  std::to_string(starts.size()) + " starts and " +
                                                  std::to_string(ends.size()) + " ends");
  }
  std::vector<Clip> clips;
  clips.reserve(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) return error(ErrorCode::kInvalidArgument, index_name("clipNames", i) + ": empty name");
    for (std::size_t j = 0; j < i; ++j) {
      if (names[j] == names[i]) {
        return error(ErrorCode::kInvalidArgument,
                     index_name("clipNames", i) + ": '" + names[i] + "' is also " + index_name("clipNames", j));
      }
    }
    if (!std::isfinite(starts[i]) || !std::isfinite(ends[i])) {
      return error(ErrorCode::kInvalidArgument, index_name("clipStarts", i) + ": clip times must be finite");
    }
    if (ends[i] < starts[i]) {
      return error(ErrorCode::kInvalidArgument, index_name("clipEnds", i) + ": " + std::to_string(ends[i]) +
                                                    " is before " + index_name("clipStarts", i) + " " +
                                                    std::to_string(starts[i]));
    }
    clips.push_back(Clip{names[i], starts[i], ends[i]});
  }
  return clips;
}

void compute_clips(ComputeContext& c) {
  namespace a = clips_attr;
  const auto& names = c.get<std::vector<std::string>>(a::kClipNames);
  const auto checked = check_clips(names, c.get<std::vector<double>>(a::kClipStarts),
                                   c.get<std::vector<double>>(a::kClipEnds));
  const auto count = static_cast<std::int64_t>(names.size());
  const std::int64_t active = c.get<std::int64_t>(a::kActive);
  c.output(a::kActiveClip) = count == 0 ? std::int64_t{0} : std::clamp<std::int64_t>(active, 0, count - 1);
  c.output(a::kError) = checked ? std::string() : checked.status().message();
}

AttrSpec input(std::string name, AttrType type, graph::Value value) {
  return graph::input_attr(std::move(name), type, std::move(value), {"activeClip", "error"});
}

}  // namespace

Status register_clip_types(graph::Registry& registry) {
  graph::NodeTypeSpec spec;
  spec.name = kAnimClipsType;
  spec.description = "The animation clips of a character (name, start, end) and which one plays";
  spec.attrs = {
      input("clipNames", {ValueType::kString, true}, std::vector<std::string>{}),
      input("clipStarts", {ValueType::kDouble, true}, std::vector<double>{}),
      input("clipEnds", {ValueType::kDouble, true}, std::vector<double>{}),
      input("active", {ValueType::kInt, false}, std::int64_t{0}),
      graph::output_attr("activeClip", {ValueType::kInt, false}),
      graph::output_attr("error", {ValueType::kString, false}, graph::kHidden),
  };
  spec.compute = compute_clips;
  return registry.add(std::move(spec));
}

Result<std::vector<Clip>> clips_of(const graph::Graph& graph, graph::NodeId clips_node) {
  namespace a = clips_attr;
  const graph::Node* node = graph.node(clips_node);
  if (node == nullptr || node->type().name() != kAnimClipsType) {
    return error(ErrorCode::kNotFound, "not an animClips node");
  }
  // Inputs only: their stored values are current without evaluation.
  auto clips = check_clips(std::get<std::vector<std::string>>(node->value(a::kClipNames)),
                           std::get<std::vector<double>>(node->value(a::kClipStarts)),
                           std::get<std::vector<double>>(node->value(a::kClipEnds)));
  if (!clips) return clips.status().with_context(node->name());
  return clips;
}

graph::NodeId find_clips_node(const graph::Graph& graph) {
  graph::NodeId best;
  std::uint64_t best_order = 0;
  for (graph::NodeId id : graph.nodes()) {
    const graph::Node* node = graph.node(id);
    if (node->type().name() != kAnimClipsType) continue;
    if (!best.is_valid() || node->order() < best_order) {
      best = id;
      best_order = node->order();
    }
  }
  return best;
}

Result<int> resolve_clip(const graph::Graph& graph, graph::NodeId clips_node, std::string_view name_or_index) {
  auto clips = clips_of(graph, clips_node);
  if (!clips) return clips.status();
  for (std::size_t i = 0; i < clips->size(); ++i) {
    if ((*clips)[i].name == name_or_index) return static_cast<int>(i);
  }
  int index = -1;
  const char* end = name_or_index.data() + name_or_index.size();
  const auto [ptr, ec] = std::from_chars(name_or_index.data(), end, index);
  if (ec == std::errc() && ptr == end && index >= 0 && static_cast<std::size_t>(index) < clips->size()) return index;
  std::string choices;
  for (std::size_t i = 0; i < clips->size(); ++i) {
    choices += (i == 0 ? "" : ", ") + std::to_string(i) + " '" + (*clips)[i].name + "'";
  }
  return error(ErrorCode::kNotFound, "no clip '" + std::string(name_or_index) + "'; clips: " +
                                         (choices.empty() ? std::string("none") : choices));
}

Status set_active_clip(graph::Graph& graph, graph::NodeId clips_node, int index) {
  auto clips = clips_of(graph, clips_node);
  if (!clips) return clips.status();
  if (index < 0 || static_cast<std::size_t>(index) >= clips->size()) {
    return error(ErrorCode::kInvalidArgument, "clip index " + std::to_string(index) + " out of range (" +
                                                  std::to_string(clips->size()) + " clips)");
  }
  return graph.set_value(graph::Plug{clips_node, clips_attr::kActive}, std::int64_t{index});
}

}  // namespace rigel::ops::anim
