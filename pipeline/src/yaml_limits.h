#pragma once
/// \file Limits on a YAML config before it is loaded: anchors and aliases may expand a small file
/// into billions of nodes (each alias stands for a copy of what its anchor names), and deep
/// nesting costs time and stack. A config is read in one pass of yaml-cpp's event parser, which
/// counts the nodes as they would be after every alias is expanded and the depth at every node,
/// and stops at the first limit passed.

#include <cstddef>
#include <string>

namespace slipfit::pipeline::detail {

constexpr std::size_t kMostYamlNodes = 1000000;  ///< after alias expansion
constexpr std::size_t kDeepestYaml = 64;         ///< nested lists and maps

/// Throws ConfigError naming \a path, the line and the limit when \a text expands past
/// kMostYamlNodes nodes, nests deeper than kDeepestYaml levels, holds a second document or an
/// alias inside the anchor it names (a cycle).
/// Syntax errors are left to the loader (which says them with their place).
void checkYamlLimits(const std::string& text, const std::string& path);

}  // namespace slipfit::pipeline::detail
