#include "slipfit/pipeline/output_files.h"

#include "slipfit/pipeline/errors.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

namespace slipfit::pipeline {

namespace fs = std::filesystem;

OutputFiles::~OutputFiles() {
  std::error_code ec;
  for (const auto& [tmp, final_path] : pending_)
    fs::remove(tmp, ec);
}

void OutputFiles::add(const std::string& name,
                      const std::function<void(const std::string& path)>& write) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw RunError("output.dir '" + dir_ + "': cannot create the directory (" +
                   (ec ? ec.message() : std::string("not a directory")) + ")");
  const fs::path final_path = fs::path(dir_) / name;
  for (const std::string& input : protected_)
    if (fs::equivalent(final_path, input, ec))
      throw RunError("output '" + final_path.string() + "' is the input '" + input +
                     "': nothing is written over it; choose another name or output.dir");
  // Same directory, so that the final rename is atomic; the extension stays last so that writers
  // that look at it (PLY, OFF) still recognise the format.
  const fs::path tmp =
      fs::path(dir_) / ("." + final_path.stem().string() + ".tmp" + std::to_string(::getpid()) +
                        final_path.extension().string());
  pending_.emplace_back(tmp.string(), final_path.string());
  try {
    write(tmp.string());
  } catch (const RunError&) {
    throw;
  } catch (const std::exception& e) {
    throw RunError("output '" + final_path.string() + "': " + e.what());
  }
  if (!fs::exists(tmp, ec))
    throw RunError("output '" + final_path.string() + "': the writer produced no file");
}

void OutputFiles::addText(const std::string& name, const std::string& text) {
  add(name, [&](const std::string& path) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out)
      throw RunError("cannot write '" + path + "' (disk full?)");
  });
}

std::vector<std::string> OutputFiles::commit() {
  std::vector<std::string> written;
  for (const auto& [tmp, final_path] : pending_) {
    std::error_code ec;
    fs::rename(tmp, final_path, ec);
    if (ec)
      throw RunError("output '" + final_path + "': cannot rename into place (" + ec.message() +
                     ")");
    written.push_back(final_path);
  }
  pending_.clear();
  return written;
}

}  // namespace slipfit::pipeline
