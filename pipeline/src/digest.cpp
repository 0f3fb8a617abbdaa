#include "digest.h"

#include <cstdio>
#include <fstream>
#include <vector>

namespace slipfit::pipeline::detail {

namespace {

constexpr std::uint64_t kOffset = 14695981039346656037ull, kPrime = 1099511628211ull;

std::uint64_t update(std::uint64_t h, const char* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= kPrime;
  }
  return h;
}

}  // namespace

std::uint64_t digest(const std::string& text) {
  return update(kOffset, text.data(), text.size());
}

bool fileDigest(const std::string& path, std::uint64_t& value, std::uint64_t& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return false;
  std::vector<char> buffer(1 << 20);
  value = kOffset;
  bytes = 0;
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    value = update(value, buffer.data(), n);
    bytes += n;
  }
  return in.eof() && !in.bad();
}

std::string hex(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

}  // namespace slipfit::pipeline::detail
