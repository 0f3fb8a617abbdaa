#pragma once
/// \file Plain values packed into a byte string and read back in the same order: what the ranks of
/// a tiled run tell each other (WorkDistribution::allGather). The ranks are processes of one
/// build on one kind of machine, so the values travel as their bytes.

#include "slipfit/pipeline/errors.h"

#include <cstring>
#include <string>
#include <type_traits>

namespace slipfit::pipeline::tiling {

/// Appends \a value's bytes to \a out.
template <typename T>
void pack(std::string& out, const T& value) {
  static_assert(std::is_trivially_copyable_v<T>, "only plain values travel as bytes");
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

/// Appends \a text with its length.
inline void packText(std::string& out, const std::string& text) {
  pack(out, static_cast<std::uint64_t>(text.size()));
  out += text;
}

/// Reads back what pack and packText appended, in order; RunError past the end (a rank that
/// packed something else).
class Unpack {
 public:
  explicit Unpack(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T next() {
    static_assert(std::is_trivially_copyable_v<T>, "only plain values travel as bytes");
    need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::string text() {
    const auto n = static_cast<std::size_t>(next<std::uint64_t>());
    need(n);
    std::string t = bytes_.substr(at_, n);
    at_ += n;
    return t;
  }
  bool done() const { return at_ == bytes_.size(); }

 private:
  void need(std::size_t n) const {
    if (n > bytes_.size() - at_)
      throw RunError("a rank's message ends early (ranks of different builds?)");
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
};

}  // namespace slipfit::pipeline::tiling
