#include "segments_las.h"

#include "../las/las_reader.h"
#include "../las/las_writer.h"
#include "ply_rows.h"

#include "slipfit/pipeline/cloud_stream.h"
#include "slipfit/pipeline/errors.h"

#include <fstream>
#include <set>

namespace slipfit::pipeline::tiling {

namespace {

/// The fields segments.ply gets from the segmentation: label and primitive go to the LAS file,
/// the normals and the segment colours do not (the untiled segments.las has neither).
const std::set<std::string> kStageFields = {"label", "primitive"};
const std::set<std::string> kNotWritten = {"x",   "y",        "z",        "nx",       "ny",
                                           "nz",  "normal_x", "normal_y", "normal_z", "curvature",
                                           "red", "green",    "blue"};
/// Input fields segments.ply renames input_<name> because the segmentation writes <name> (its
/// colours take a packed input colour's place too).
const std::set<std::string> kRenamed = {"label", "primitive", "red", "green",
                                        "blue",  "rgb",       "rgba"};

/// The rows of a merged segments.ply.
class PlyRows : public las::LasRows {
 public:
  explicit PlyRows(const std::string& ply) : in_(ply) {
    for (const StreamField& f : in_.fields()) {
      if (kNotWritten.count(f.name))
        continue;
      const bool stage = kStageFields.count(f.name) > 0;
      std::string name = f.name;
      if (!stage && name.rfind("input_", 0) == 0 && kRenamed.count(name.substr(6)))
        name = name.substr(6);
      fields_.push_back({name, f.scalar, stage});
      at_.push_back(fieldAt(f));
    }
    for (int a = 0; a < 3; ++a) {
      const StreamField* f = findField(in_.fields(), std::string(1, "xyz"[a]));
      if (!f)
        throw RunError("'" + ply + "': no " + "xyz"[a] + " coordinate");
      xyz_[a] = fieldAt(*f);
    }
  }
  std::uint64_t size() const override { return in_.size(); }
  const std::vector<las::LasField>& fields() const override { return fields_; }
  void load(std::uint64_t first, std::uint64_t count) override {
    in_.readRecords(first, count, rows_);  // one read: the coordinates are in the rows
  }
  double coordinate(std::uint64_t k, int axis) const override {
    return xyz_[axis].get(rows_.data() + k * in_.recordBytes());
  }
  double value(std::size_t field, std::uint64_t k) const override {
    return at_[field].get(rows_.data() + k * in_.recordBytes());
  }

 private:
  CloudStream in_;
  std::vector<las::LasField> fields_;
  std::vector<FieldAt> at_;
  std::vector<char> rows_;
  FieldAt xyz_[3];
};

/// Whether the file at \a path starts as a LAS file does.
bool isLas(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  return in.read(magic, 4) && std::string(magic, 4) == "LASF";
}

}  // namespace

void writeSegmentsLas(const std::string& ply, const std::string& input, const std::string& path) {
  las::LasSource source;
  if (isLas(input)) {
    const las::LasHeader header = las::readLasHeader(input, "'" + input + "': ");
    source.format = header.format;
    source.scale = header.scale;
    source.offset = header.offset;
  }
  PlyRows rows(ply);
  las::writeLas(rows, source, path);
}

}  // namespace slipfit::pipeline::tiling
