#pragma once
// Where this build's checkout and build tree are, for what runs from the
// build tree: the shipped config that edsp-gap and edsp-blind-rig read by
// default, the tests' fixtures and the programs they start. Defined in a
// source CMake writes into each build tree (build_paths.cpp.in), not passed
// as compile definitions: then no other object depends on where the checkout
// lies, and a fresh clone elsewhere finds every other object in the compiler
// cache.

#include <string>
#include <string_view>

namespace edsp {

// The checkout this tree was configured from.
const std::string& SourceDir();
// SourceDir()/relative, e.g. SourcePath("config/huang2021.toml").
std::string SourcePath(std::string_view relative);
// The build tree/relative, e.g. BuildPath("lcmtypes/edsp_lcmtypes.jar").
std::string BuildPath(std::string_view relative);
// An edsp program of this build tree, e.g. BuiltProgram("edsp-gap").
std::string BuiltProgram(std::string_view program);

}  // namespace edsp
