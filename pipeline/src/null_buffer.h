#pragma once
/// \file A stream buffer that swallows everything written to it: the report of a --quiet run and
/// of a tile's own run.

#include <streambuf>

namespace slipfit::pipeline::detail {

class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c; }
};

}  // namespace slipfit::pipeline::detail
