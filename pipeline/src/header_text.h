#pragma once
/// \file Reading the text header of a PLY or PCD file: its first bytes, and its lines' words.

#include <cstdint>
#include <string>
#include <vector>

namespace slipfit::pipeline::detail {

/// The most of a file read as its header: a header longer than this is refused.
constexpr std::size_t kMaxHeaderBytes = 1 << 20;

/// The file's first kMaxHeaderBytes (fewer when it is shorter), and its size (0 when unknown).
std::string readHead(const std::string& path, std::uint64_t& file_size);

/// The words of \a line between runs of \a separators.
std::vector<std::string> tokens(const std::string& line, const char* separators);

/// Fields between runs of separators, with an empty first or last field when the line starts or
/// ends with a separator (boost::split with token_compress_on, as PCL splits obj_info lines).
std::vector<std::string> splitKeepingEnds(const std::string& line, const char* separators);

/// A plain decimal number (no sign, no exponent, no trailing text) no larger than \a max.
bool parseCount(const std::string& text, std::uint64_t max, std::uint64_t& value);

}  // namespace slipfit::pipeline::detail
