#include "slipfit/pipeline/cloud_io.h"

#include "slipfit/pipeline/errors.h"

#include "data_guard.h"
#include "file_checks.h"
#include "header_guard.h"
#include "las/las_reader.h"
#include "ply/ply_header.h"
#include "sensor_view.h"

#include <pcl/PCLPointField.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

namespace slipfit::pipeline {

namespace fs = std::filesystem;
using Field = pcl::PCLPointField;

namespace {

static_assert(sizeof(SlippageType) == sizeof(std::int32_t), "written as an int property");
using ply::datatypeBytes;

/// The value at \a p of a PCLPointField \a datatype as double; NaN for a type PCL 1.13 does not
/// know.
double valueAt(const std::uint8_t* p, std::uint8_t datatype) {
  const std::optional<ply::Scalar> scalar = ply::scalarOfDatatype(datatype);
  return scalar ? ply::decode(*scalar, p) : std::numeric_limits<double>::quiet_NaN();
}

/// The PLY type of a PCLPointField \a datatype (double for one PCL 1.13 does not know).
ply::Scalar plyScalarOf(std::uint8_t datatype) {
  return ply::scalarOfDatatype(datatype).value_or(ply::Scalar::f64);
}

const Field* findField(const pcl::PCLPointCloud2& blob, const char* name) {
  for (const auto& f : blob.fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

bool isGeometryField(const std::string& name) {
  static const char* const kNames[] = {"x",        "y",  "z",  "normal_x", "normal_y",
                                       "normal_z", "nx", "ny", "nz",       "curvature"};
  return std::any_of(std::begin(kNames), std::end(kNames),
                     [&](const char* n) { return name == n; });
}

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// The extension of a cloud file slipfit reads (.ply, .pcd, .las), lower-cased; RunError for
/// another, or for an empty file.
std::string readableExtension(const std::string& path, const std::string& where) {
  const std::string ext = lowerExtension(path);
  if (ext == ".laz")
    throw RunError(where + "compressed LAS (LAZ): decompress it first, e.g. `pdal translate " +
                   "in.laz out.las` or `laszip -i in.laz -o out.las`");
  if (ext != ".ply" && ext != ".pcd" && ext != ".las")
    throw RunError(where + "unsupported file type '" + ext + "' (expected .ply, .pcd or .las)");
  std::error_code ec;
  if (fs::file_size(path, ec) == 0)
    throw RunError(where + "the file is empty");
  return ext;
}

void appendField(pcl::PCLPointCloud2& blob, const std::string& name, std::uint8_t datatype) {
  Field f;
  f.name = name;
  f.offset = blob.point_step;
  f.datatype = datatype;
  f.count = 1;
  blob.fields.push_back(f);
  blob.point_step += static_cast<std::uint32_t>(datatypeBytes(datatype));
}

/// Where the values of each written field live: a pointer to the first one and a stride, so that
/// rows can be packed chunk by chunk straight from the point data.
struct Column {
  const std::uint8_t* base;
  std::size_t stride;
  std::size_t size;
  /// A coordinate written in the input's frame: the float at base + this, as double when size is
  /// 8 (else float).
  std::optional<double> shift;
};

/// The fields a cloud is written with (header.fields, point_step, width; no data) and their
/// sources.
struct RowLayout {
  pcl::PCLPointCloud2 header;
  std::vector<Column> columns;

  /// Rows [first, first + count) packed into \a out (count × point_step bytes).
  void pack(std::size_t first, std::size_t count, std::uint8_t* out) const {
    for (std::size_t i = 0; i < count; ++i) {
      std::uint8_t* row = out + i * header.point_step;
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const Column& column = columns[c];
        const std::uint8_t* from = column.base + (first + i) * column.stride;
        if (!column.shift) {
          std::memcpy(row + header.fields[c].offset, from, column.size);
          continue;
        }
        float local;
        std::memcpy(&local, from, sizeof(float));
        const double value = static_cast<double>(local) + *column.shift;
        if (column.size == sizeof(double)) {
          std::memcpy(row + header.fields[c].offset, &value, sizeof(double));
        } else {
          const auto narrow = static_cast<float>(value);
          std::memcpy(row + header.fields[c].offset, &narrow, sizeof(float));
        }
      }
    }
  }
};

RowLayout rowLayout(const PointData& data) {
  const auto& cloud = *data.cloud;
  const std::size_t n = cloud.size();
  RowLayout layout;
  pcl::PCLPointCloud2& h = layout.header;
  h.height = 1;
  h.width = static_cast<std::uint32_t>(n);
  h.is_bigendian = false;
  h.is_dense = true;
  auto add = [&](const std::string& name, std::uint8_t type, const void* base, std::size_t stride) {
    appendField(h, name, type);
    layout.columns.push_back(
        {static_cast<const std::uint8_t*>(base), stride, datatypeBytes(type), std::nullopt});
  };
  const auto* first = reinterpret_cast<const std::uint8_t*>(cloud.data());
  const std::size_t ps = sizeof(pcl::PointNormal);
  // Coordinates go back to the input's frame, as double when the input's were.
  const std::uint8_t coordinate = data.frame.double_coordinates ? Field::FLOAT64 : Field::FLOAT32;
  add("x", coordinate, first + offsetof(pcl::PointNormal, x), ps);
  add("y", coordinate, first + offsetof(pcl::PointNormal, y), ps);
  add("z", coordinate, first + offsetof(pcl::PointNormal, z), ps);
  for (int axis = 0; axis < 3; ++axis)
    if (data.frame.double_coordinates || data.frame.shift[axis] != 0.0)
      layout.columns[static_cast<std::size_t>(axis)].shift = data.frame.shift[axis];
  if (data.has_normals) {
    add("normal_x", Field::FLOAT32, first + offsetof(pcl::PointNormal, normal_x), ps);
    add("normal_y", Field::FLOAT32, first + offsetof(pcl::PointNormal, normal_y), ps);
    add("normal_z", Field::FLOAT32, first + offsetof(pcl::PointNormal, normal_z), ps);
  }
  if (data.has_curvature)
    add("curvature", Field::FLOAT32, first + offsetof(pcl::PointNormal, curvature), ps);
  const bool stage_colours = std::any_of(data.fields.begin(), data.fields.end(),
                                         [](const auto& f) { return f.name == "red"; });
  if (data.extra.width == n)
    for (const auto& f : data.extra.fields) {
      const std::uint8_t* base = data.extra.data.data() + f.offset;
      const std::size_t stride = data.extra.point_step;
      // PCL packs PLY colours into one 32-bit rgb(a) field (0xAARRGGBB, little-endian in
      // memory); viewers want them back as uchar red, green, blue (alpha). A stage that colours
      // the points (segmentation) takes the names; the input's colours then keep their packed
      // field under input_rgb(a), so that PCL and viewers show the stage's colours.
      const bool packed = (f.name == "rgb" || f.name == "rgba") && datatypeBytes(f.datatype) == 4;
      if (packed && !stage_colours) {
        add("red", Field::UINT8, base + 2, stride);
        add("green", Field::UINT8, base + 1, stride);
        add("blue", Field::UINT8, base + 0, stride);
        if (f.name == "rgba")
          add("alpha", Field::UINT8, base + 3, stride);
      } else {
        // An input field a stage also writes (label, red, ...) keeps its values under
        // input_<name>: a PLY with two properties of one name is read back by no one.
        const auto taken = [&](const std::string& name) {
          return std::any_of(data.fields.begin(), data.fields.end(),
                             [&](const auto& g) { return g.name == name; }) ||
                 (name != f.name && std::any_of(data.extra.fields.begin(), data.extra.fields.end(),
                                                [&](const auto& g) { return g.name == name; }));
        };
        std::string name = packed ? "input_" + f.name : f.name;
        while (taken(name))
          name = "input_" + name;
        add(name, f.datatype, base, stride);
      }
    }
  for (const auto& f : data.fields) {
    const std::size_t count = std::visit([](const auto& v) { return v.size(); }, f.values);
    if (count != n)
      throw RunError("output: field '" + f.name + "' has " + std::to_string(count) +
                     " values for " + std::to_string(n) + " points");
    if (const auto* v = std::get_if<std::vector<std::int32_t>>(&f.values))
      add(f.name, Field::INT32, v->data(), sizeof(std::int32_t));
    else if (const auto* w = std::get_if<std::vector<float>>(&f.values))
      add(f.name, Field::FLOAT32, w->data(), sizeof(float));
    else if (const auto* c = std::get_if<std::vector<std::uint8_t>>(&f.values))
      add(f.name, Field::UINT8, c->data(), sizeof(std::uint8_t));
    else if (const auto* t = std::get_if<std::vector<SlippageType>>(&f.values))
      add(f.name, Field::INT32, t->data(), sizeof(SlippageType));  // its int code
  }
  h.row_step = h.point_step * h.width;
  return layout;
}

std::string plyHeader(const pcl::PCLPointCloud2& h, const char* format) {
  std::vector<ply::Property> properties;
  properties.reserve(h.fields.size());
  for (const auto& f : h.fields)
    properties.push_back({f.name, plyScalarOf(f.datatype)});
  return ply::headerText(format, static_cast<std::uint64_t>(h.width) * h.height, properties);
}

/// Appends one row as text: the shortest decimal that reads back to each value.
void appendAsciiRow(const pcl::PCLPointCloud2& h, const std::uint8_t* row, std::string& line) {
  char buffer[64];
  for (std::size_t c = 0; c < h.fields.size(); ++c) {
    const Field& f = h.fields[c];
    char* stop =
        ply::print(plyScalarOf(f.datatype), row + f.offset, buffer, buffer + sizeof(buffer));
    if (c)
      line += ' ';
    line.append(buffer, stop);
  }
  line += '\n';
}

bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  std::uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

}  // namespace

Eigen::Vector3d globalShift(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const double extent = std::max((hi - lo).maxCoeff(), 1.0);
  const double largest = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).maxCoeff();
  if (!(largest > 16.0 * extent))
    return Eigen::Vector3d::Zero();
  const double step = std::pow(10.0, std::ceil(std::log10(extent)));
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  return (centre / step).array().round().matrix() * step;
}

namespace {

/// The points are analysed in float: squared distances (neighbour search, fits) must neither
/// overflow (coordinates past ~1e19 square past FLT_MAX: FLANN aborts, normals fail) nor underflow
/// (a cloud 1e-30 across squares under FLT_MIN). Throws RunError unless the local coordinates
/// (after the global shift) reach at most kFarthestLocal and the cloud spans at least
/// kNarrowestSpan (or nothing: a single point is refused later for what it is).
constexpr double kFarthestLocal = 1e18, kNarrowestSpan = 1e-12;
void checkFloatSpan(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                    const std::string& where) {
  const double farthest = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).maxCoeff();
  const double span = (hi - lo).maxCoeff();
  std::ostringstream why;
  why << std::setprecision(3);
  if (farthest > kFarthestLocal)
    why << where << "its coordinates reach " << farthest << " (after any global shift), past the "
        << kFarthestLocal << " whose squared distances float holds; scale the cloud to other units";
  else if (span > 0.0 && span < kNarrowestSpan)
    why << where << "the cloud spans only " << span << ", under the " << kNarrowestSpan
        << " whose squared distances float holds; scale the cloud to other units";
  if (!why.str().empty())
    throw RunError(why.str());
}

/// A file read by PCL into a blob, with the sensor pose its header gives.
struct ReadBlob {
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  std::size_t points = 0;
};

/// Reads \a path (.ply or .pcd, its header checked first) with PCL's reader; RunError for
/// anything malformed, truncated, empty or whose fields do not fit their records.
ReadBlob readBlob(const std::string& path, bool ply, const std::string& where) {
  if (ply) {
    detail::checkPlyHeader(path, where);
    detail::checkPlyData(path, where);
  } else {
    detail::checkPcdHeaderText(path, where);  // and its data
  }
  ReadBlob r;
  pcl::PCLPointCloud2& blob = r.blob;
  int version = 0;
  int rc = -1;
  try {
    if (ply) {
      pcl::PLYReader reader;
      rc = reader.read(path, blob, r.origin, r.orientation, version, 0);
    } else {
      // PCL 1.13's PCDReader::read dereferences null on some malformed headers that announce no
      // points (found by tests/fuzz): the header is checked on its own first.
      pcl::PCDReader reader;
      int data_type = 0;
      unsigned int data_index = 0;
      rc =
          reader.readHeader(path, blob, r.origin, r.orientation, version, data_type, data_index, 0);
      if (rc >= 0 && (blob.fields.empty() || blob.point_step == 0))
        rc = -1;
      else if (rc >= 0)
        detail::checkPcdLayout(blob, where);
      if (rc >= 0 && static_cast<std::size_t>(blob.width) * blob.height == 0)
        throw RunError(where + "the cloud is empty (0 points)");
      if (rc >= 0)
        rc = reader.read(path, blob, r.origin, r.orientation, version, 0);
    }
  } catch (const RunError&) {
    throw;
  } catch (const std::exception& e) {
    throw RunError(where + "cannot be read: " + e.what());
  }
  if (rc < 0)
    throw RunError(where + "not a readable " + (ply ? "PLY" : "PCD") +
                   " file (malformed or truncated)");
  const std::size_t n = static_cast<std::size_t>(blob.width) * blob.height;
  if (blob.data.size() != n * blob.point_step)
    throw RunError(where + "truncated: the header announces " + std::to_string(n) +
                   " points but the data holds " +
                   std::to_string(blob.point_step ? blob.data.size() / blob.point_step : 0));
  if (n == 0)
    throw RunError(where + "the cloud is empty (0 points)");
  // Every field must fit its record: a header whose SIZE, TYPE and COUNT disagree would have the
  // reads below run past the data (found by tests/fuzz).
  for (const auto& f : blob.fields) {
    const std::size_t size = datatypeBytes(f.datatype) * std::max<std::uint32_t>(f.count, 1);
    if (datatypeBytes(f.datatype) == 0 || f.offset + size > blob.point_step)
      throw RunError(where + "field '" + f.name +
                     "' does not fit its record (inconsistent size, type or count)");
  }
  r.points = n;
  return r;
}

/// The geometry fields of a blob and its values as double.
struct GeometryFields {
  const pcl::PCLPointCloud2& blob;
  const Field *x = nullptr, *y = nullptr, *z = nullptr;
  const Field *nx = nullptr, *ny = nullptr, *nz = nullptr, *curvature = nullptr;
  bool has_normals = false;

  double value(std::size_t row, const Field* f) const {
    return valueAt(blob.data.data() + row * blob.point_step + f->offset, f->datatype);
  }
  Eigen::Vector3d point(std::size_t row) const {
    return {value(row, x), value(row, y), value(row, z)};
  }
  /// Row \a i has a usable normal: finite and not zero.
  bool normalOk(std::size_t i) const {
    const double a = value(i, nx), b = value(i, ny), c = value(i, nz);
    return std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && a * a + b * b + c * c > 0.0;
  }
};

/// x, y, z (RunError when absent), the normals as normal_x/y/z or nx/ny/nz (absent when every
/// one is zero: a file whose normals are all zero has placeholders, not normals), curvature.
GeometryFields geometryFields(const pcl::PCLPointCloud2& blob, std::size_t n,
                              const std::string& where) {
  GeometryFields g{blob};
  g.x = findField(blob, "x");
  g.y = findField(blob, "y");
  g.z = findField(blob, "z");
  if (!g.x || !g.y || !g.z)
    throw RunError(where + "no x, y, z fields");
  const auto either = [&](const char* a, const char* b) {
    const Field* f = findField(blob, a);
    return f ? f : findField(blob, b);
  };
  g.nx = either("normal_x", "nx");
  g.ny = either("normal_y", "ny");
  g.nz = either("normal_z", "nz");
  g.has_normals = g.nx && g.ny && g.nz;
  g.curvature = findField(blob, "curvature");
  if (g.has_normals) {
    bool any = false;
    for (std::size_t i = 0; i < n && !any; ++i)
      any = g.value(i, g.nx) != 0.0 || g.value(i, g.ny) != 0.0 || g.value(i, g.nz) != 0.0;
    g.has_normals = any;
  }
  return g;
}

/// The rows kept: finite coordinates within float's range (RunError at the first other one with
/// NanPolicy::error). Counts the kept rows whose normal is unusable.
std::vector<std::size_t> keptRows(const GeometryFields& g, std::size_t n, NanPolicy nan_policy,
                                  const std::string& where, std::size_t& normals_missing,
                                  std::size_t& first_missing_normal) {
  std::vector<std::size_t> keep;
  keep.reserve(n);
  normals_missing = 0;
  first_missing_normal = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p = g.point(i);
    const bool finite = p.allFinite();
    const double largest = p.cwiseAbs().maxCoeff();
    const bool ok = finite && largest <= std::numeric_limits<float>::max();
    if (ok) {
      keep.push_back(i);
      if (g.has_normals && !g.normalOk(i) && normals_missing++ == 0)
        first_missing_normal = i;
    } else if (nan_policy == NanPolicy::error) {
      std::ostringstream what;
      if (finite)
        what << " has a coordinate beyond float's range (" << largest << " > 3.4e38)";
      else
        what << " has a non-finite coordinate (NaN, inf or not a number)";
      throw RunError(where + "point " + std::to_string(i) + what.str() +
                     "; set input.nan: skip to drop such points");
    }
  }
  if (keep.empty())
    throw RunError(where + "none of its " + std::to_string(n) + " points has finite values");
  return keep;
}

/// The sensor's view of a PCD: organized, or with a VIEWPOINT that is not the identity at the
/// origin; nullopt otherwise.
std::optional<SensorPose> sensorPose(const ReadBlob& r, bool pcd, const Eigen::Vector3d& shift) {
  if (!pcd ||
      !isSensorView(r.origin.head<3>().cast<double>(), r.orientation.cast<double>(), r.blob.height))
    return std::nullopt;
  SensorPose sensor;
  sensor.origin = r.origin.head<3>().cast<double>() - shift;
  sensor.orientation = r.orientation.cast<double>().normalized();
  sensor.width = r.blob.width;
  sensor.height = r.blob.height;
  return sensor;
}

/// The kept rows as points (shifted by the frame's shift), with their normals and curvature
/// where usable (NaN otherwise).
void fillCloud(const GeometryFields& g, const std::vector<std::size_t>& keep, PointData& data) {
  const Eigen::Vector3d& shift = data.frame.shift;
  auto& cloud = *data.cloud;
  cloud.resize(keep.size());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t j = 0; j < keep.size(); ++j) {
    const std::size_t i = keep[j];
    pcl::PointNormal& p = cloud[j];
    p.x = static_cast<float>(g.value(i, g.x) - shift.x());
    p.y = static_cast<float>(g.value(i, g.y) - shift.y());
    p.z = static_cast<float>(g.value(i, g.z) - shift.z());
    const bool normal = g.has_normals && g.normalOk(i);
    if (normal) {
      p.normal_x = static_cast<float>(g.value(i, g.nx));
      p.normal_y = static_cast<float>(g.value(i, g.ny));
      p.normal_z = static_cast<float>(g.value(i, g.nz));
    } else {
      p.normal_x = p.normal_y = p.normal_z = nan;
    }
    p.curvature = data.has_curvature && normal ? static_cast<float>(g.value(i, g.curvature)) : nan;
  }
  cloud.width = static_cast<std::uint32_t>(keep.size());
  cloud.height = 1;
  cloud.is_dense = true;
}

/// A field of the input carried to the outputs as it is.
struct CarriedField {
  std::string name;
  std::uint8_t datatype = 0;
  std::size_t offset = 0;  ///< in the input's record
};

/// Every field of the kept rows that is not read as geometry, with its own type, into
/// data.extra; returns them. A field of COUNT k > 1 (PCD) is carried as name_0 … name_{k−1};
/// normal components that do not make a normal (nx without ny and nz, say) and a curvature
/// without normals are carried as input_<name> (the normals slipfit writes have those names).
std::vector<CarriedField> carryExtraFields(const pcl::PCLPointCloud2& blob, const GeometryFields& g,
                                           const std::vector<std::size_t>& keep, PointData& data) {
  std::vector<CarriedField> extra;
  for (const auto& f : blob.fields) {
    const std::size_t bytes = datatypeBytes(f.datatype);
    if (f.name == "_" || bytes == 0)
      continue;
    std::string name = f.name;
    if (isGeometryField(f.name)) {
      const bool read =
          f.name == "x" || f.name == "y" || f.name == "z" ||
          (g.has_normals && (&f == g.nx || &f == g.ny || &f == g.nz || &f == g.curvature));
      // All-zero normals are placeholders (geometryFields): dropped, as documented there.
      const bool placeholder =
          !g.has_normals && g.nx && g.ny && g.nz && (&f == g.nx || &f == g.ny || &f == g.nz);
      if (read || placeholder)
        continue;
      name = "input_" + f.name;
    }
    const std::uint32_t count = std::max<std::uint32_t>(f.count, 1);
    for (std::uint32_t k = 0; k < count; ++k)
      extra.push_back(
          {count == 1 ? name : name + "_" + std::to_string(k), f.datatype, f.offset + k * bytes});
  }
  pcl::PCLPointCloud2& out = data.extra;
  out.height = 1;
  out.width = static_cast<std::uint32_t>(keep.size());
  out.is_bigendian = false;
  out.is_dense = true;
  for (const CarriedField& f : extra)
    appendField(out, f.name, f.datatype);
  out.row_step = out.point_step * out.width;
  out.data.resize(static_cast<std::size_t>(out.row_step));
  for (std::size_t j = 0; j < keep.size(); ++j)
    for (std::size_t e = 0; e < extra.size(); ++e)
      std::memcpy(out.data.data() + j * out.point_step + out.fields[e].offset,
                  blob.data.data() + keep[j] * blob.point_step + extra[e].offset,
                  datatypeBytes(extra[e].datatype));
  return extra;
}

}  // namespace

unsigned inputDataBits(const std::string& path) {
  const std::string where = "input '" + path + "': ";
  detail::checkReadableFile(path, where, "a point cloud file");
  const std::string ext = readableExtension(path, where);
  if (ext == ".las") {
    las::readLasHeader(path, where);
    return kPoints;  // LAS records have no normals
  }
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0, rc = -1;
  unsigned int data_index = 0;
  try {
    if (ext == ".ply") {
      detail::checkPlyHeader(path, where);
      pcl::PLYReader reader;
      rc = reader.readHeader(path, blob, origin, orientation, version, data_type, data_index, 0);
    } else {
      detail::checkPcdHeaderText(path, where);
      pcl::PCDReader reader;
      rc = reader.readHeader(path, blob, origin, orientation, version, data_type, data_index, 0);
    }
  } catch (const RunError&) {
    throw;
  } catch (const std::exception& e) {
    throw RunError(where + "cannot be read: " + e.what());
  }
  if (rc < 0)
    throw RunError(where + "not a readable " + (ext == ".ply" ? "PLY" : "PCD") +
                   " file (malformed or truncated)");
  const auto named = [&](const char* a, const char* b) {
    return std::any_of(blob.fields.begin(), blob.fields.end(),
                       [&](const Field& f) { return f.name == a || f.name == b; });
  };
  const bool normals =
      named("normal_x", "nx") && named("normal_y", "ny") && named("normal_z", "nz");
  return kPoints | (normals ? kNormals : 0u);
}

PointData readCloud(const std::string& path, NanPolicy nan_policy, ReadReport* report) {
  const std::string where = "input '" + path + "': ";
  detail::checkReadableFile(path, where, "a point cloud file");
  const std::string ext = readableExtension(path, where);
  ReadBlob read;
  las::LasHeader las_header;
  if (ext == ".las") {
    read.blob = las::readLas(path, where, &las_header);
    read.points = static_cast<std::size_t>(read.blob.width) * read.blob.height;
  } else {
    read = readBlob(path, ext == ".ply", where);
  }
  const std::size_t n = read.points;
  const GeometryFields g = geometryFields(read.blob, n, where);
  std::size_t normals_missing = 0, first_missing_normal = 0;
  const std::vector<std::size_t> keep =
      keptRows(g, n, nan_policy, where, normals_missing, first_missing_normal);

  PointData data;
  data.has_normals = g.has_normals;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const std::size_t i : keep) {
    lo = lo.cwiseMin(g.point(i));
    hi = hi.cwiseMax(g.point(i));
  }
  data.frame.double_coordinates = g.x->datatype == Field::FLOAT64 ||
                                  g.y->datatype == Field::FLOAT64 ||
                                  g.z->datatype == Field::FLOAT64;
  // 32-bit integers hold what float cannot (2^31 as float is 256 apart): shifted as doubles are.
  const auto wide = [](const Field* f) {
    return f->datatype == Field::FLOAT64 || f->datatype == Field::INT32 ||
           f->datatype == Field::UINT32;
  };
  if (wide(g.x) || wide(g.y) || wide(g.z))
    data.frame.shift = globalShift(lo, hi);
  if (data.frame.shift != Eigen::Vector3d::Zero())
    data.frame.double_coordinates = true;  // written back as double: float cannot hold them
  checkFloatSpan(lo - data.frame.shift, hi - data.frame.shift, where);
  if (ext == ".las") {
    data.frame.grid_scale = Eigen::Vector3d(las_header.scale.data());
    data.frame.grid_offset = Eigen::Vector3d(las_header.offset.data());
    data.frame.las_format = las_header.format;
  }
  data.sensor = sensorPose(read, ext == ".pcd", data.frame.shift);
  if (data.sensor && data.sensor->height > 1)  // organized: a kept row's index is its pixel
    data.pixels.assign(keep.begin(), keep.end());
  data.has_curvature = g.has_normals && g.curvature != nullptr;
  fillCloud(g, keep, data);
  const std::vector<CarriedField> extra = carryExtraFields(read.blob, g, keep, data);

  if (report) {
    report->points_read = n;
    report->dropped = n - keep.size();
    report->normals = g.has_normals;
    report->normals_missing = normals_missing;
    report->largest_coordinate = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).maxCoeff();
    report->first_missing_normal = first_missing_normal;
    report->extra_fields.clear();
    for (const CarriedField& f : extra)
      report->extra_fields += (report->extra_fields.empty() ? "" : ", ") + f.name;
  }
  return data;
}

pcl::PCLPointCloud2 toBlob(const PointData& data) {
  const RowLayout layout = rowLayout(data);
  pcl::PCLPointCloud2 blob = layout.header;
  blob.data.resize(static_cast<std::size_t>(blob.row_step));
  layout.pack(0, blob.width, blob.data.data());
  return blob;
}

void writeCloudPly(const PointData& data, const std::string& path, bool binary) {
  if (data.size() == 0)
    throw RunError("output '" + path + "': no points to write");
  // Written in chunks straight from the point data: PCL's PLYWriter needs the whole cloud as one
  // PCLPointCloud2 (a second copy of every point), prints ASCII values with 6 digits, and reports
  // success on a truncated file when the disk is full.
  const RowLayout layout = rowLayout(data);
  const pcl::PCLPointCloud2& h = layout.header;
  std::ofstream out(path, std::ios::binary);
  if (!out)
    throw RunError("output '" + path + "': cannot be opened for writing");
  const char* format = !binary                ? "ascii"
                       : hostIsLittleEndian() ? "binary_little_endian"
                                              : "binary_big_endian";
  const std::string header = plyHeader(h, format);
  out << header;
  // Chunks of at most 4 MB (and no more rows than the cloud has): 65,536 rows whatever their
  // width took 260 KB per float property, 2.6 GB for 10,000 properties of 2,000 points.
  const std::size_t n = data.size();
  const std::size_t kChunk =
      std::min(n, std::max<std::size_t>(1, (std::size_t{4} << 20) / h.point_step));
  std::vector<std::uint8_t> rows(kChunk * h.point_step);
  std::string text;
  for (std::size_t first = 0; first < n && out; first += kChunk) {
    const std::size_t count = std::min(kChunk, n - first);
    layout.pack(first, count, rows.data());
    if (binary) {
      out.write(reinterpret_cast<const char*>(rows.data()),
                static_cast<std::streamsize>(count * h.point_step));
    } else {
      text.clear();
      for (std::size_t i = 0; i < count; ++i)
        appendAsciiRow(h, rows.data() + i * h.point_step, text);
      out << text;
    }
  }
  out.close();
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!out || ec || (binary && size != header.size() + n * h.point_step))
    throw RunError("output '" + path + "': write failed (disk full?)");
}

}  // namespace slipfit::pipeline
