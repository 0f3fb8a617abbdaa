#include "ply_header.h"

namespace slipfit::pipeline::ply {

std::string headerText(const char* format, std::uint64_t count,
                       const std::vector<Property>& properties) {
  std::string text = std::string("ply\nformat ") + format +
                     " 1.0\ncomment slipfit\nelement vertex " + std::to_string(count) + "\n";
  for (const Property& p : properties) {
    std::string name = p.name;
    if (name.rfind("normal_", 0) == 0)
      name = "n" + name.substr(7);
    text += std::string("property ") + scalarName(p.scalar) + " " + name + "\n";
  }
  return text + "end_header\n";
}

}  // namespace slipfit::pipeline::ply
