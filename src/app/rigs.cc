// The workspace's rigs and definitions (workspace.h): the Rig Manager's
// operations, stepping and features (seed 003), edit mode, live rebuilds and
// versioned saves.

#include <algorithm>
#include <fstream>
#include <sstream>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"

namespace rigel::app {

using internal::conflict;
using internal::make_parent;
using internal::saved;

// ---- rigs at step 0 ------------------------------------------------------------
//
// The scene keeps nothing of a rig with no step built (its metaRoot is step
// 1's work), so the workspace keeps its definition, to list the rig and step
// it forward again, as a Build object held in Python does. An entry stands
// while the scene has no rig of its name and the undo history is at or
// after the step that made it: undoing that step hides it (the rig is
// back), redo shows it again, and a new edit made from before it drops it
// for good.

const Workspace::Unbuilt* Workspace::unbuilt_rig(const std::string& name) const {
  auto it = unbuilt_.find(name);
  if (it == unbuilt_.end() || graph().undo_count() < it->second.since || rig::find_rig(graph(), name).is_valid())
    return nullptr;
  return &it->second;
}

std::vector<std::uint64_t> Workspace::unbuilt_undone() const {
  std::vector<std::uint64_t> out;
  for (const auto& [name, u] : unbuilt_)
    if (u.since > graph().undo_count()) out.push_back(u.serial);
  return out;
}

void Workspace::drop_unbuilt(const std::vector<std::uint64_t>& undone) {
  if (undone.empty() || graph().can_redo()) return;
  for (auto it = unbuilt_.begin(); it != unbuilt_.end();)
    it = std::find(undone.begin(), undone.end(), it->second.serial) != undone.end() ? unbuilt_.erase(it) : std::next(it);
}

Status Workspace::check_rig(const std::string& name, bool unbuilt_too, const std::string& field) {
  if (rig::find_rig(graph(), name).is_valid()) return Status::ok();
  if (unbuilt_rig(name)) {
    if (unbuilt_too) return Status::ok();
    return Status(ErrorCode::kFailedPrecondition,
                  field + ": '" + name + "' is at step 0 (nothing built): step it forward first")
        .with_field(field);
  }
  return Status(ErrorCode::kNotFound, field + ": the scene has no rig '" + name + "'").with_field(field);
}

Result<std::unique_ptr<rig::Build>> Workspace::open_rig(const std::string& name) {
  if (const Unbuilt* u = unbuilt_rig(name)) {
    auto b = rig::Build::open(*scene_, u->definition, factory_, u->options);
    if (!b) return conflict(b.status());
    return b;
  }
  auto b = rig::Build::reopen(*scene_, name, factory_);
  if (!b) return conflict(b.status());
  return b;
}

std::vector<FeatureState> Workspace::features_of(const rig::Build& build) {
  std::vector<FeatureState> list;
  for (const rig::PlannedStep& p : build.plan()) {
    if (p.feature.empty()) continue;
    const bool seen = std::any_of(list.begin(), list.end(), [&](const FeatureState& f) {
      return f.feature == p.feature && f.switch_name == p.switch_name;
    });
    if (seen) continue;
    bool enabled = true;
    for (const rig::Feature& f : build.definition().features) {
      if (f.name != p.feature) continue;
      enabled = f.enabled;
      if (!p.switch_name.empty())
        for (const rig::FeatureSwitch& sw : f.switches)
          if (sw.name == p.switch_name) enabled = enabled && sw.enabled;
    }
    list.push_back(FeatureState{p.feature, p.switch_name, enabled});
  }
  return list;
}

std::vector<RigEntry> Workspace::rigs() {
  std::vector<RigEntry> out;
  for (NodeId r : rig::list_rigs(graph())) {
    RigEntry e;
    e.name = rig::meta_string(graph(), r, "rigName");
    auto build = rig::Build::reopen(*scene_, e.name, factory_);
    if (build) {
      e.steps = static_cast<int>((*build)->plan().size());
      e.features = features_of(**build);
      e.version = (*build)->definition().version;
      e.definition = (*build)->definition().source;
      e.edit_mode = (*build)->edit_mode();
    }
    out.push_back(std::move(e));
  }
  for (const auto& [name, u] : unbuilt_) {
    if (!unbuilt_rig(name)) continue;
    auto build = open_rig(name);
    if (!build) continue;
    const rig::Definition& def = (*build)->definition();
    RigEntry e;
    e.name = name;
    e.unbuilt = true;
    e.steps = static_cast<int>((*build)->plan().size());
    e.features = features_of(**build);
    e.version = def.version;
    e.definition = def.source;
    e.edit_mode = (*build)->edit_mode();
    std::error_code ec;
    if (!def.source.empty() && fs::is_regular_file(def.source, ec)) {
      rig::ParseResult p = rig::load_definition(def.source);
      if (p.ok()) e.definition_version = p.definition.version;
    }
    out.push_back(std::move(e));
  }
  return out;
}

Result<rig::AddedRig> Workspace::add_rig(const fs::path& path, rig::BuildOptions options) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    return Status(ErrorCode::kNotFound, "definition: no file '" + path.string() + "'").with_field("definition");
  // Every problem of the file before building.
  if (auto def = rig::read_definition(path, factory_.schemas()); !def) {
    const ErrorCode code = def.status().code() == ErrorCode::kNotFound ? ErrorCode::kNotFound : ErrorCode::kInvalidArgument;
    return Status(code, def.status().message()).with_field("definition");
  }
  auto added = rig::add_rig(*scene_, path, factory_, options);
  if (!added) return conflict(added.status(), "definition");
  bump_revision();
  return added;
}

Result<rig::UpdateReport> Workspace::update_rig(const std::string& name, const fs::path& definition, bool force,
                                                rig::Build::KeepKeys keep) {
  if (Status s = check_rig(name, false); !s) return s;
  auto r = rig::update_rig(*scene_, name, factory_, definition, force, keep);
  if (!r) return conflict(r.status());
  bump_revision();
  return r;
}

Status Workspace::remove_rig(const std::string& name) {
  if (Status s = check_rig(name, true); !s) return s;
  if (unbuilt_rig(name)) {
    // Nothing of it is in the scene: it leaves the list.
    unbuilt_.erase(name);
    bump_revision();
    return Status::ok();
  }
  unbuilt_.erase(name);
  auto build = rig::Build::reopen(*scene_, name, factory_);
  if (!build) return conflict(build.status());
  graph::Transaction tx(graph(), "remove rig " + name);
  if (Status s = (*build)->remove(); !s) {
    tx.rollback();
    return conflict(s);
  }
  bump_revision();
  return Status::ok();
}

Result<StepReport> Workspace::step_rig(const std::string& name, std::optional<int> to, int by) {
  if (Status s = check_rig(name, true); !s) return s;
  auto build = open_rig(name);
  if (!build) return build.status();
  rig::Build& b = **build;
  const bool was_built = b.position() > 0;
  const int steps = static_cast<int>(b.plan().size());
  int target = b.position();
  if (to) {
    if (*to < 0 || *to > steps)
      return Status(ErrorCode::kInvalidArgument, "to: expected a step from 0 to " + std::to_string(steps)).with_field("to");
    target = *to;
  } else {
    target = static_cast<int>(std::clamp(static_cast<long long>(target) + by, 0LL, static_cast<long long>(steps)));
  }
  {
    graph::Transaction tx(graph(), "step " + name + " to " + std::to_string(target));
    if (Status s = b.go_to(target); !s) {
      tx.rollback();
      return conflict(s);
    }
  }
  const int position = b.position();
  if (position == 0 && was_built)
    unbuilt_[name] = Unbuilt{b.definition(), b.options(), graph().undo_count(), ++unbuilt_serial_};
  bump_revision();
  StepReport report{name, position, steps, {}, {}};
  if (position > 0) {
    const rig::PlannedStep& last = b.plan()[static_cast<std::size_t>(position - 1)];
    report.step = last.label();
    if (last.component >= 0) report.rig_id = b.components()[static_cast<std::size_t>(last.component)]->rig_id;
  }
  return report;
}

Result<FeatureReport> Workspace::set_feature(const std::string& name, const std::string& feature,
                                             const std::string& switch_name, bool enabled) {
  if (Status s = check_rig(name, true); !s) return s;
  auto build = open_rig(name);
  if (!build) return build.status();
  rig::Build& b = **build;
  const bool known = std::any_of(b.plan().begin(), b.plan().end(), [&](const rig::PlannedStep& p) { return p.feature == feature; });
  if (!known) {
    return Status(ErrorCode::kNotFound, "feature: no step of rig '" + name + "' names feature '" + feature + "'")
        .with_field("feature");
  }
  graph::Transaction tx(graph(), std::string(enabled ? "enable " : "disable ") + feature);
  if (Status s = b.set_feature(feature, enabled, switch_name); !s) {
    tx.rollback();
    return conflict(s, "feature");
  }
  if (b.position() == 0) {
    auto it = unbuilt_.find(name);
    if (it != unbuilt_.end()) it->second.definition = b.definition();
  }
  bump_revision();
  return FeatureReport{name, features_of(b), b.position(), static_cast<int>(b.plan().size())};
}

Result<bool> Workspace::set_edit_mode(const std::string& name, bool on) {
  if (Status s = check_rig(name, true); !s) return s;
  auto build = open_rig(name);
  if (!build) return build.status();
  if (Status s = (*build)->set_edit_mode(on); !s) return conflict(s);
  if ((*build)->position() == 0) {
    auto it = unbuilt_.find(name);
    if (it != unbuilt_.end()) it->second.options.edit_mode = (*build)->edit_mode();
  }
  bump_revision();
  return (*build)->edit_mode();
}

Result<CommitReport> Workspace::commit_edits(const std::string& name, const fs::path& out, bool keep_editing) {
  if (Status s = check_rig(name, false); !s) return s;
  auto build = rig::Build::reopen(*scene_, name, factory_);
  if (!build) return conflict(build.status());
  fs::path def_path = out.empty() ? fs::path((*build)->definition().source) : out;
  if (!def_path.empty()) {
    std::error_code ec;
    const fs::path absolute = fs::absolute(def_path, ec);
    if (!ec) def_path = absolute.lexically_normal();
  }
  // The rig records the file its moved guides are saved to (so it is up to
  // date with it) and leaves edit mode unless asked not to.
  auto edits = (*build)->commit_edits(def_path.string(), !keep_editing);
  if (!edits) return conflict(edits.status());
  if (!edits->changed.empty()) {
    if (def_path.empty())
      return Status(ErrorCode::kInvalidArgument, "definitionOut: the rig has no definition path; give one")
          .with_field("definitionOut");
    if (Status s = make_parent(def_path, "definitionOut"); !s) return s;
    if (Status s = saved(rig::save_definition(edits->definition, def_path), "definitionOut"); !s) return s;
  }
  bump_revision();
  CommitReport report;
  report.rig = name;
  report.version = edits->definition.version;
  report.changed = edits->changed;
  report.ignored = edits->ignored;
  report.definition = std::move(edits->definition);
  if (!report.changed.empty()) report.definition_path = def_path;
  report.edit_mode = (*build)->edit_mode();
  return report;
}

Result<rig::Definition> Workspace::definition(const std::string& name) {
  if (Status s = check_rig(name, true); !s) return s;
  auto build = open_rig(name);
  if (!build) return build.status();
  return (*build)->definition();
}

std::vector<std::string> Workspace::component_types() const { return factory_.schemas().types(); }

// ---- definitions ---------------------------------------------------------------

CheckedDefinition Workspace::check_definition(const std::string& text, rig::Syntax syntax, const std::string& where) const {
  rig::ParseResult p = rig::parse_definition(text, syntax, where, factory_.schemas());
  if (!p.ok()) return {std::move(p.definition), std::move(p.errors)};
  std::vector<rig::Diagnostic> problems = rig::validate(p.definition, factory_.schemas());
  return {std::move(p.definition), std::move(problems)};
}

Result<BuildReport> Workspace::build_definition(rig::Definition def) {
  if (std::vector<rig::Diagnostic> problems = rig::validate(def, factory_.schemas()); !problems.empty())
    return Status(ErrorCode::kInvalidArgument, "definition: " + problems.front().str()).with_field("definition");
  const std::string name = def.name;
  BuildReport report{name, {}};
  if (rig::find_rig(graph(), name).is_valid()) {
    auto build = rig::Build::reopen(*scene_, name, factory_);
    if (!build) return conflict(build.status(), "definition");
    def.source = (*build)->definition().source;
    graph::Transaction tx(graph(), "rebuild " + name);
    Status s = (*build)->position() < static_cast<int>((*build)->plan().size()) ? (*build)->build_all() : Status::ok();
    if (s) {
      auto r = (*build)->rebuild_changed(std::move(def), rig::Build::Rebuild::kChanged);
      if (r) report.rebuilt = std::move(*r);
      else s = r.status();
    }
    if (!s) {
      tx.rollback();
      return conflict(s, "definition");
    }
  } else {
    def.source.clear();  // built from a client: no file behind it yet
    graph::Transaction tx(graph(), "build " + name);
    auto build = rig::Build::open(*scene_, std::move(def), factory_);
    if (!build) {
      tx.rollback();
      return conflict(build.status(), "definition");
    }
    if (Status s = (*build)->build_all(); !s) {
      tx.rollback();
      return conflict(s, "definition");
    }
    for (const rig::Component* c : (*build)->components()) report.rebuilt.push_back(c->rig_id);
  }
  bump_revision();
  return report;
}

Result<SavedDefinition> Workspace::save_definition(rig::Definition def, const fs::path& path) {
  const auto syntax = rig::syntax_of(path);
  if (!syntax)
    return Status(ErrorCode::kInvalidArgument, "path: '" + path.string() + "' is neither .rig.xml nor .rig.json").with_field("path");
  if (std::vector<rig::Diagnostic> problems = rig::validate(def, factory_.schemas()); !problems.empty())
    return Status(ErrorCode::kInvalidArgument, "definition: " + problems.front().str()).with_field("definition");
  if (Status s = make_parent(path, "path"); !s) return s;
  // Saving over a definition with other content makes a new version.
  def.version = internal::version_to_save(
      path, def.version,
      [&]() -> std::optional<std::string> {
        rig::ParseResult old = rig::load_definition(path, factory_.schemas());
        if (!old.ok()) return std::nullopt;
        return old.definition.version;
      },
      [&](const std::string& v) {
        rig::Definition same = def;
        same.version = v;
        return rig::write_definition(same, *syntax);
      });
  def.source = path.string();
  if (Status s = saved(rig::save_definition(def, path), "path"); !s) return s;
  return SavedDefinition{path, def.version};
}

}  // namespace rigel::app
