#pragma once
/// \file 64-bit FNV-1a digests of texts and files: what a resumed tiled run compares to know that a
/// file is the one it wrote, and how ranks compare their configs. A check against accidents
/// (truncation, a half-written file, another run's file), not against an adversary.

#include <cstdint>
#include <string>

namespace slipfit::pipeline::detail {

std::uint64_t digest(const std::string& text);

/// The digest and size of the file at \a path; false when it cannot be read.
bool fileDigest(const std::string& path, std::uint64_t& digest, std::uint64_t& bytes);

/// \a value as 16 hexadecimal digits.
std::string hex(std::uint64_t value);

}  // namespace slipfit::pipeline::detail
