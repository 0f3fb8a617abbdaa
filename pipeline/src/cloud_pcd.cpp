#include "slipfit/pipeline/cloud_io.h"

#include "slipfit/pipeline/errors.h"

#include <pcl/PCLPointField.h>
#include <pcl/common/io.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace slipfit::pipeline {

namespace {

using Field = pcl::PCLPointField;

const Field* findField(const pcl::PCLPointCloud2& blob, const char* name, std::uint8_t datatype) {
  for (const auto& f : blob.fields)
    if (f.name == name && f.datatype == datatype && f.count == 1)
      return &f;
  return nullptr;
}

/// \a rows (one per point of \a data) scattered to their pixels of the sensor's width × height
/// grid, as an organized cloud: a pixel without a point holds NaN in every float field and zero
/// in the others (PCL's organized clouds mark a missing return by NaN coordinates). \a rows
/// unchanged when \a data is no organized view (no grid, or its points are not one per pixel).
pcl::PCLPointCloud2 organized(const PointData& data, pcl::PCLPointCloud2 rows) {
  if (!data.sensor || data.sensor->height <= 1 || data.pixels.size() != rows.width * rows.height)
    return rows;
  const std::size_t cells = std::size_t{data.sensor->width} * data.sensor->height;
  std::vector<char> taken(cells, 0);
  for (const std::int32_t p : data.pixels) {
    if (p < 0 || static_cast<std::size_t>(p) >= cells || taken[static_cast<std::size_t>(p)])
      return rows;
    taken[static_cast<std::size_t>(p)] = 1;
  }
  pcl::PCLPointCloud2 grid;
  grid.header = rows.header;
  grid.fields = rows.fields;
  grid.point_step = rows.point_step;
  grid.is_bigendian = rows.is_bigendian;
  grid.width = data.sensor->width;
  grid.height = data.sensor->height;
  grid.row_step = grid.point_step * grid.width;
  grid.is_dense = false;
  // One empty pixel's record, copied to every pixel before the points are.
  std::vector<std::uint8_t> empty(rows.point_step, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double nan_double = std::numeric_limits<double>::quiet_NaN();
  for (const Field& f : rows.fields)
    for (std::uint32_t c = 0; c < std::max<std::uint32_t>(f.count, 1); ++c) {
      if (f.datatype == Field::FLOAT32)
        std::memcpy(empty.data() + f.offset + 4 * c, &nan, 4);
      else if (f.datatype == Field::FLOAT64)
        std::memcpy(empty.data() + f.offset + 8 * c, &nan_double, 8);
    }
  grid.data.resize(cells * grid.point_step);
  for (std::size_t k = 0; k < cells; ++k)
    std::memcpy(grid.data.data() + k * grid.point_step, empty.data(), grid.point_step);
  for (std::size_t i = 0; i < data.pixels.size(); ++i)
    std::memcpy(grid.data.data() + static_cast<std::size_t>(data.pixels[i]) * grid.point_step,
                rows.data.data() + i * rows.point_step, rows.point_step);
  return grid;
}

/// Cuts the zeros PCL 1.13's PCDWriter::writeBinary leaves after a PCLPointCloud2's data (up to
/// a page): the file ends where its \a data_bytes of data do.
void dropPadding(const std::string& path, std::size_t data_bytes) {
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::string mark = "\nDATA binary\n";
  const std::size_t at = head.find(mark);
  if (at == std::string::npos)
    throw RunError("output '" + path + "': PCL's PCD writer wrote no binary data");
  const std::uintmax_t end = at + mark.size() + data_bytes;
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) > end)
    std::filesystem::resize_file(path, end, ec);
  if (ec)
    throw RunError("output '" + path + "': " + ec.message());
}

}  // namespace

pcl::PCLPointCloud2 toPclConventions(const pcl::PCLPointCloud2& blob) {
  const Field* rgb[3] = {findField(blob, "red", Field::UINT8),
                         findField(blob, "green", Field::UINT8),
                         findField(blob, "blue", Field::UINT8)};
  const bool pack = rgb[0] && rgb[1] && rgb[2];
  pcl::PCLPointCloud2 out;
  out.header = blob.header;
  out.width = blob.width;
  out.height = blob.height;
  out.is_bigendian = blob.is_bigendian;
  out.is_dense = blob.is_dense;
  // Every field but the colour channels, in order; the packed colour where red was.
  struct Copy {
    std::uint32_t from, to, bytes;
  };
  std::vector<Copy> copies;
  std::uint32_t rgb_at = 0;
  for (const Field& f : blob.fields) {
    const bool channel = pack && (&f == rgb[1] || &f == rgb[2]);
    if (channel)
      continue;
    Field g = f;
    g.offset = out.point_step;
    if (pack && &f == rgb[0]) {
      g.name = "rgb";
      g.datatype = Field::UINT32;
      rgb_at = g.offset;
      out.point_step += 4;
    } else {
      // −1 (no segment) is 0xFFFFFFFF in two's complement: the same bytes, read as PCL's mark of
      // an unlabelled point (OrganizedConnectedComponentSegmentation's).
      if (f.name == "label" && f.datatype == Field::INT32)
        g.datatype = Field::UINT32;
      const std::uint32_t bytes =
          std::max<std::uint32_t>(f.count, 1) * pcl::getFieldSize(f.datatype);
      copies.push_back({f.offset, g.offset, bytes});
      out.point_step += bytes;
    }
    out.fields.push_back(g);
  }
  const std::size_t n = static_cast<std::size_t>(blob.width) * blob.height;
  out.row_step = out.point_step * out.width;
  out.data.resize(n * out.point_step);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* row = blob.data.data() + i * blob.point_step;
    std::uint8_t* target = out.data.data() + i * out.point_step;
    for (const Copy& c : copies)
      std::memcpy(target + c.to, row + c.from, c.bytes);
    if (pack) {
      // 0xAARRGGBB, opaque, as PCL's PointXYZRGB holds it.
      const std::uint32_t packed = 0xff000000u | std::uint32_t{row[rgb[0]->offset]} << 16 |
                                   std::uint32_t{row[rgb[1]->offset]} << 8 | row[rgb[2]->offset];
      std::memcpy(target + rgb_at, &packed, 4);
    }
  }
  return out;
}

void writeCloudPcd(const PointData& data, const std::string& path, bool binary) {
  if (data.size() == 0)
    throw RunError("output '" + path + "': no points to write");
  const pcl::PCLPointCloud2 blob = organized(data, toPclConventions(toBlob(data)));
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  if (data.sensor) {
    origin.head<3>() = (data.sensor->origin + data.frame.shift).cast<float>();
    orientation = data.sensor->orientation.cast<float>();
  }
  pcl::PCDWriter writer;
  int status = -1;
  try {
    // ascii: 17 significant digits, which read back every float and double exactly.
    status = binary ? writer.writeBinary(path, blob, origin, orientation)
                    : writer.writeASCII(path, blob, origin, orientation, 17);
  } catch (const std::exception& e) {
    throw RunError("output '" + path + "': " + e.what());
  }
  std::error_code ec;
  if (status != 0 || !std::filesystem::exists(path, ec))
    throw RunError("output '" + path + "': PCL's PCD writer failed (disk full?)");
  if (binary)
    dropPadding(path, blob.data.size());
}

}  // namespace slipfit::pipeline
