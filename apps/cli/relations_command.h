#pragma once
// `rigel ephemeral relations`: lists an ephemeral rig's relations between
// controls, or edits them (--add, --remove, --set-kind, --group, applied in
// command-line order as one transaction). ephemeral_commands.cc registers
// its options.

#include <optional>
#include <string>
#include <vector>

namespace rigel::cli {

struct EphemeralRelationsArgs {
  std::string scene;
  std::optional<std::string> rig;
  std::vector<std::string> add, remove, set_kind, group;
  std::optional<std::string> output;
  bool json = false;
};

// One edit, in command-line order (run_ephemeral_commands() reads the order
// off the parser).
struct RelationEdit {
  enum class Op { kAdd, kRemove, kSetKind, kGroup } op;
  std::string text;  // the option's value, as given
};

// Runs the command: `edits` in command-line order.
int run_ephemeral_relations(const EphemeralRelationsArgs& args, const std::vector<RelationEdit>& edits);

}  // namespace rigel::cli
