// Graph: the compiled evaluation (Evaluation::kCompiled). The program is
// made from the schedule once per topology generation; a step refreshes its
// node's dirty inputs by typed copies between the values' storage and runs
// the node's compute, exactly as update_node() does through the
// connections, so the two evaluations give bit-identical values.
#include <algorithm>
#include <atomic>
#include <string>
#include <tuple>

#include "graph_internal.h"

namespace rigel::graph {
namespace {

// Where a plug's scalar storage is inside its node's value: the value
// itself, or one component of a double3; nullptr for arrays and elements.
void* storage(Value& value, std::int8_t component) {
  if (component >= 0) {
    auto* v = std::get_if<Vec3>(&value);
    return v ? &(*v)[component] : nullptr;
  }
  return std::visit(
      [](auto& held) -> void* {
        using T = std::decay_t<decltype(held)>;
        if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::int64_t> || std::is_same_v<T, double> ||
                      std::is_same_v<T, Vec3> || std::is_same_v<T, Quat> || std::is_same_v<T, Mat4>)
          return &held;
        return nullptr;
      },
      value);
}

// The typed copy for a connection between two scalar plugs whose storage
// holds the same alternative; kGeneric when they do not.
ProgramCopy copy_kind(const Value& src, std::int8_t src_component, const Value& dst, std::int8_t dst_component) {
  if (src_component >= 0 || dst_component >= 0) {
    const bool src_double = src_component >= 0 ? std::holds_alternative<Vec3>(src) : std::holds_alternative<double>(src);
    const bool dst_double = dst_component >= 0 ? std::holds_alternative<Vec3>(dst) : std::holds_alternative<double>(dst);
    return src_double && dst_double ? ProgramCopy::kDouble : ProgramCopy::kGeneric;
  }
  if (src.index() != dst.index()) return ProgramCopy::kGeneric;
  if (std::holds_alternative<double>(src)) return ProgramCopy::kDouble;
  if (std::holds_alternative<Vec3>(src)) return ProgramCopy::kDouble3;
  if (std::holds_alternative<Quat>(src)) return ProgramCopy::kQuat;
  if (std::holds_alternative<Mat4>(src)) return ProgramCopy::kMatrix;
  if (std::holds_alternative<std::int64_t>(src)) return ProgramCopy::kInt;
  if (std::holds_alternative<bool>(src)) return ProgramCopy::kBool;
  return ProgramCopy::kGeneric;
}

// The typed copy of a scalar plug into an element of an array.
ProgramCopy element_copy_kind(const Value& src, std::int8_t src_component, const Value& dst) {
  if (src_component >= 0 || std::holds_alternative<double>(src))
    return (src_component < 0 || std::holds_alternative<Vec3>(src)) && std::holds_alternative<std::vector<double>>(dst)
               ? ProgramCopy::kDoubleElement
               : ProgramCopy::kGeneric;
  if (std::holds_alternative<Vec3>(src) && std::holds_alternative<std::vector<Vec3>>(dst)) return ProgramCopy::kDouble3Element;
  if (std::holds_alternative<Mat4>(src) && std::holds_alternative<std::vector<Mat4>>(dst)) return ProgramCopy::kMatrixElement;
  return ProgramCopy::kGeneric;
}

template <typename T>
void copy_value(const ProgramOp& op) {
  *static_cast<T*>(op.dst) = *static_cast<const T*>(op.src);
}

// False when the element is past the array's end (the caller grows it).
template <typename T>
bool copy_element(const ProgramOp& op) {
  std::vector<T>& array = std::get<std::vector<T>>(*static_cast<Value*>(op.dst));
  if (static_cast<std::size_t>(op.element) >= array.size()) return false;
  array[static_cast<std::size_t>(op.element)] = *static_cast<const T*>(op.src);
  return true;
}

// Prefetches every cache line of `bytes` bytes at `at`.
void prefetch_lines(const void* at, std::size_t bytes) {
  constexpr std::size_t kLine = 64;
  const char* first = static_cast<const char*>(at);
  for (std::size_t b = 0; b < bytes; b += kLine) __builtin_prefetch(first + b);
}

}  // namespace

const char* evaluation_name(Evaluation evaluation) {
  return evaluation == Evaluation::kCompiled ? "compiled" : "interpreted";
}

Result<Evaluation> evaluation_from_name(std::string_view name) {
  if (name == "interpreted") return Evaluation::kInterpreted;
  if (name == "compiled") return Evaluation::kCompiled;
  return error(ErrorCode::kInvalidArgument,
               "unknown evaluation '" + std::string(name) + "' (expected interpreted or compiled)");
}

void Graph::compile() {
  if (evaluation_ == Evaluation::kCompiled) (void)program();
}

const Graph::Program& Graph::program() {
  const Schedule& s = schedule();
  if (!program_) program_ = std::make_unique<Program>();
  Program& p = *program_;
  if (p.generation == topology_generation_) return p;
  // Made on every topology edit (a constraint added is one), so it touches
  // no node: each step's copies are resolved when it first runs.
  p.steps.assign(s.order.size(), ProgramStep{});
  p.ops.resize(s.inputs.size());
  p.ready = std::make_unique<std::atomic<std::uint8_t>[]>(s.order.size());
  for (std::size_t k = 0; k < s.order.size(); ++k) {
    const NodeId id = s.order[k];
    ProgramStep& step = p.steps[k];
    step.node = slots_[id.index].get();
    std::tie(step.ops_begin, step.ops_end) = s.input_range[id.index];
  }
  for (std::size_t i = 0; i < s.inputs.size(); ++i) {
    p.ops[i] = ProgramOp{};
    p.ops[i].dst_attr = s.inputs[i].dst_attr;
    p.ops[i].input = &s.inputs[i];
  }
  p.time_marks_made = false;
  p.generation = topology_generation_;
  return p;
}

void Graph::Program::prefetch(std::uint32_t k) const {
  const ProgramStep& step = steps[k];
  prefetch_lines(step.node, sizeof(Node));
  // Another thread may be resolving the step (a parallel evaluation): its
  // pointers are read only once it has published them.
  if (!ready[k].load(std::memory_order_acquire)) return;
  __builtin_prefetch(step.dirty);
  __builtin_prefetch(step.versions);
  for (std::uint32_t i = step.ops_begin; i < step.ops_end; ++i)
    if (ops[i].dst) prefetch_lines(ops[i].dst, 65);  // a value may straddle two lines
  for (AttrIndex o : step.outputs) prefetch_lines(step.values + o, sizeof(Value));
}

void Graph::Program::prefetch_flags(std::size_t k) const {
  const ProgramStep& step = steps[k];
  prefetch_lines(step.node, sizeof(Node));
  if (!ready[k].load(std::memory_order_acquire)) return;
  __builtin_prefetch(step.dirty);
  __builtin_prefetch(step.connections);
}

void Graph::run_step(const Program& p, std::uint32_t k) {
  // On the step's first run: the typed copy of each input connection and
  // where the node's values are. Only this step's own entries are written,
  // by the one thread running it.
  Program& own = const_cast<Program&>(p);
  const auto resolve = [&] {
    ProgramStep& step = own.steps[k];
    Node& n = *step.node;
    step.compute = n.type_->compute();
    for (std::uint32_t i = step.ops_begin; i < step.ops_end; ++i) {
      ProgramOp& op = own.ops[i];
      const ScheduledInput& in = *op.input;
      const Connection& c = *in.connection;
      step.enums |= in.enum_dst;
      if (c.src.element < 0 && c.dst.element >= 0 && c.dst.component < 0) {
        Value& src = const_cast<Node*>(in.src)->values_[c.src.attr];
        Value& dst = n.values_[c.dst.attr];
        op.copy = element_copy_kind(src, c.src.component, dst);
        op.src = storage(src, c.src.component);
        op.dst = &dst;
        op.element = c.dst.element;
        if (!op.src) op.copy = ProgramCopy::kGeneric;
      } else if (c.src.element < 0 && c.dst.element < 0) {
        // Computes never change a value's alternative, so these pointers
        // hold until the topology changes (a node created or deleted).
        Value& src = const_cast<Node*>(in.src)->values_[c.src.attr];
        Value& dst = n.values_[c.dst.attr];
        op.copy = copy_kind(src, c.src.component, dst, c.dst.component);
        op.src = storage(src, c.src.component);
        op.dst = storage(dst, c.dst.component);
        if (!op.src || !op.dst) op.copy = ProgramCopy::kGeneric;
      }
    }
    step.values = n.values_.data();
    step.dirty = n.dirty_.data();
    step.versions = n.versions_.data();
    step.connections = n.outputs_.data();
    step.outputs = n.type_->outputs();
    own.ready[k].store(1, std::memory_order_release);
  };
  if (!p.ready[k].load(std::memory_order_acquire)) resolve();
  const ProgramStep& step = p.steps[k];
  Node& n = *step.node;
  const ProgramOp* first = p.ops.data() + step.ops_begin;
  const ProgramOp* last = p.ops.data() + step.ops_end;
  // The interpreted refresh, for what has no typed copy.
  const auto refresh = [&](const ScheduledInput& in) {
    if (in.whole) n.values_[in.dst_attr] = in.src->values_[in.src_attr];
    else write_part(n.values_[in.dst_attr], n.type_->attr(in.dst_attr).type, in.connection->dst, plug_value(in.connection->src));
  };
  // As update_node(): refresh the dirty connected inputs, then clear their
  // flags (several connections may write parts of one attribute).
  for (const ProgramOp* op = first; op != last; ++op) {
    if (!n.dirty_[op->dst_attr]) continue;
    n.versions_[op->dst_attr] = ++n.clock_;
    switch (op->copy) {
      case ProgramCopy::kDouble: copy_value<double>(*op); break;
      case ProgramCopy::kDouble3: copy_value<Vec3>(*op); break;
      case ProgramCopy::kQuat: copy_value<Quat>(*op); break;
      case ProgramCopy::kMatrix: copy_value<Mat4>(*op); break;
      case ProgramCopy::kInt: copy_value<std::int64_t>(*op); break;
      case ProgramCopy::kBool: copy_value<bool>(*op); break;
      case ProgramCopy::kDoubleElement:
        if (!copy_element<double>(*op)) refresh(*op->input);
        break;
      case ProgramCopy::kDouble3Element:
        if (!copy_element<Vec3>(*op)) refresh(*op->input);
        break;
      case ProgramCopy::kMatrixElement:
        if (!copy_element<Mat4>(*op)) refresh(*op->input);
        break;
      default: refresh(*op->input); break;
    }
  }
  for (const ProgramOp* op = first; op != last; ++op) {
    if (!n.dirty_[op->dst_attr]) continue;
    n.dirty_[op->dst_attr] = 0;
    if (step.enums && op->input->enum_dst) clamp_enum(n.values_[op->dst_attr], n.type_->attr(op->dst_attr));
  }
  n.queued_ = false;
  const std::span<const AttrIndex> outputs = n.type_->outputs();
  bool compute = false;
  for (AttrIndex o : outputs) compute |= n.dirty_[o] != 0;
  if (!compute) return;
  ComputeContext context(n, time_);
  step.compute(context);
  for (AttrIndex o : outputs) n.dirty_[o] = 0;
}

}  // namespace rigel::graph
