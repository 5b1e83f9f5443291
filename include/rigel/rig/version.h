#pragma once
// Versions of rig definitions and of their components (seed 002): dotted
// numbers such as "1.0" or "2.3.10", compared part by part; a definition
// (and each component) carries one, and an update rebuilds what changed.

#include <string>
#include <string_view>

namespace rigel::rig {

// Dotted numeric versions ("1.10" > "1.9"); a non-numeric part compares as
// text, a missing part as "0" ("1.0" == "1"). Negative, zero, positive like
// strcmp.
int compare_versions(std::string_view a, std::string_view b);

// The version after `version`: its last number plus one ("1.0" -> "1.1",
// "2" -> "3", "1.0.9" -> "1.0.10", any number of digits); ".1" appended
// when it ends in no number, "1" for "". What rig edit mode
// (Build::edits) and a versioned save give a changed definition.
std::string next_version(std::string_view version);

// "1.2" -> "1.3", "2" -> "3", "1.2.9" -> "1.2.10": the last dot-separated
// part plus one when it is a number that fits 64 bits (leading zeros
// dropped: "1.09" -> "1.10"), else that part with ".1" appended ("" ->
// ".1").
std::string bump_version(std::string_view version);

}  // namespace rigel::rig
