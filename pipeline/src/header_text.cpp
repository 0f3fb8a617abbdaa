#include "header_text.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace slipfit::pipeline::detail {

std::string readHead(const std::string& path, std::uint64_t& file_size) {
  std::error_code ec;
  file_size = std::filesystem::file_size(path, ec);
  if (ec)
    file_size = 0;
  std::ifstream in(path, std::ios::binary);
  std::string head(static_cast<std::size_t>(std::min<std::uint64_t>(file_size, kMaxHeaderBytes)),
                   '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

std::vector<std::string> tokens(const std::string& line, const char* separators) {
  std::vector<std::string> out;
  std::size_t at = line.find_first_not_of(separators);
  while (at != std::string::npos) {
    const std::size_t end = line.find_first_of(separators, at);
    out.push_back(line.substr(at, end == std::string::npos ? std::string::npos : end - at));
    at = line.find_first_not_of(separators, end);
  }
  return out;
}

std::vector<std::string> splitKeepingEnds(const std::string& line, const char* separators) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (true) {
    const std::size_t end = line.find_first_of(separators, at);
    out.push_back(line.substr(at, end == std::string::npos ? std::string::npos : end - at));
    if (end == std::string::npos)
      return out;
    at = line.find_first_not_of(separators, end);
    if (at == std::string::npos) {
      out.emplace_back();
      return out;
    }
  }
}

bool parseCount(const std::string& text, std::uint64_t max, std::uint64_t& value) {
  if (text.empty() || text.size() > 19 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  value = std::stoull(text);
  return value <= max;
}

}  // namespace slipfit::pipeline::detail
