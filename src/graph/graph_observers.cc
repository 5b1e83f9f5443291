// Graph: time, frame rate, selection, and the observers told of every change.
#include "rigel/graph/graph.h"

#include <algorithm>
#include <string>

#include "graph_internal.h"

namespace rigel::graph {

// ---- time and selection ------------------------------------------------------

void Graph::set_time(double seconds) {
  if (seconds == time_) return;
  time_ = seconds;
  dirty_for_time();
  notify([&](Observer& o) { o.time_changed(*this); });
}

Status Graph::set_fps(double fps) {
  if (!(fps > 0.0) || fps > 1e6) return error(ErrorCode::kInvalidArgument, "frame rate must be positive, got " + std::to_string(fps));
  fps_ = fps;
  return Status::ok();
}

void Graph::select(std::vector<NodeId> nodes_to_select) {
  std::vector<NodeId> clean;
  for (NodeId id : nodes_to_select) {
    if (node(id) && std::find(clean.begin(), clean.end(), id) == clean.end()) clean.push_back(id);
  }
  if (clean == selection_) return;
  selection_ = std::move(clean);
  notify([&](Observer& o) { o.selection_changed(*this); });
}

// ---- observers -------------------------------------------------------------

void Graph::add_observer(Observer* observer) {
  if (std::find(observers_.begin(), observers_.end(), observer) == observers_.end()) observers_.push_back(observer);
}

void Graph::remove_observer(Observer* observer) { std::erase(observers_, observer); }

}  // namespace rigel::graph
