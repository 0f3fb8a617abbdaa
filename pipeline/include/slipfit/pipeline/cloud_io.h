#pragma once
/// \file Reading PLY/PCD into PointData and writing PointData as PLY, through PCL's readers and
/// writers. All failures throw RunError naming the file.

#include "slipfit/pipeline/point_data.h"

#include <array>
#include <string>
#include <string_view>

namespace slipfit::pipeline {

/// What to do with points that have a NaN/inf coordinate (organized scans mark missing depth so).
enum class NanPolicy { error, skip };
constexpr std::array<std::pair<NanPolicy, std::string_view>, 2> kNanPolicyNames{{
    {NanPolicy::error, "error"},
    {NanPolicy::skip, "skip"},
}};

struct ReadReport {
  std::size_t points_read = 0;  ///< points in the file
  std::size_t dropped = 0;      ///< points dropped for non-finite coordinates
  bool normals = false;         ///< the file has normals
  /// Points kept whose given normal is NaN, inf or zero: their normal is NaN (missing).
  std::size_t normals_missing = 0;
  std::size_t first_missing_normal = 0;  ///< the file's index of the first such point
  std::string extra_fields;         ///< the names of the fields carried through, comma separated
  double largest_coordinate = 0.0;  ///< the largest |x|, |y| or |z| kept
};

/// The global shift for double coordinates within [\a lo, \a hi]: zero when float keeps them
/// (the largest |coordinate| under 16 × the extent, at least 1: float's step there is at most
/// 16 × its step across the data), else the box's centre rounded to a multiple of the power of
/// ten at or above the extent, so that the shifted coordinates stay within about ± that power.
Eigen::Vector3d globalShift(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

/// Reads a .ply (ascii or binary), .pcd or .las (1.0–1.4, record formats 0–10: las_reader.h)
/// file; a .laz is refused with how to decompress it. Coordinates and normals of any numeric type
/// become float; double coordinates first lose their globalShift (PointData::frame); normals are
/// recognised as normal_x/normal_y/normal_z (PLY nx/ny/nz); every other field is kept in
/// PointData::extra with its own type. Points with a non-finite coordinate are dropped
/// (NanPolicy::skip) or refused (error); a point whose given normal is non-finite or zero is kept
/// with a NaN normal and counted in the report (the caller decides: see runner.cpp). Throws
/// RunError on a missing, unreadable, truncated or empty file, a file without x/y/z, or a
/// non-finite coordinate under NanPolicy::error.
PointData readCloud(const std::string& path, NanPolicy nan_policy, ReadReport* report = nullptr);

/// What the file at \a path gives a pipeline, from its header alone (checked as readCloud checks
/// it): kPoints, and kNormals when it names normal fields (their values are not read: normals
/// that are all zero count as none only when the cloud is read). Throws RunError as readCloud.
unsigned inputDataBits(const std::string& path);

/// Writes every point with its normals (when present), curvature (when computed), the extra fields
/// and the stage fields as one PLY vertex element, in binary or ascii; coordinates in the input's
/// frame (+ frame.shift; double when the input's were). Writes \a path directly;
/// use OutputFiles for the all-or-nothing behaviour.
void writeCloudPly(const PointData& data, const std::string& path, bool binary);

/// The PCLPointCloud2 that writeCloudPly writes (exposed for tests and other writers).
pcl::PCLPointCloud2 toBlob(const PointData& data);

/// \a blob in PCL's own conventions, as its point types hold them: uchar red, green and blue
/// packed into one uint32 `rgb` (0xAARRGGBB, opaque) where red was, and an int `label` as uint32
/// (−1, no segment, becomes 4294967295: the mark of an unlabelled point in PCL's
/// OrganizedConnectedComponentSegmentation). Other fields are unchanged.
pcl::PCLPointCloud2 toPclConventions(const pcl::PCLPointCloud2& blob);

/// Writes the cloud writeCloudPly writes as a PCD in PCL's conventions (toPclConventions),
/// with the input sensor's pose as its VIEWPOINT: pcl::io::loadPCDFile reads it into
/// pcl::PointXYZRGBL, PointXYZLNormal or PointXYZRGBNormal with the labels and colours. A
/// sensor's organized view (data.sensor with rows, each point's pixel in data.pixels) is written
/// organized, width × height, NaN where the sensor had no return: read back, it is the same view.
/// Writes \a path directly; use OutputFiles for the all-or-nothing behaviour.
/// \a binary false: DATA ascii, every value to 17 significant digits.
void writeCloudPcd(const PointData& data, const std::string& path, bool binary = true);

}  // namespace slipfit::pipeline
