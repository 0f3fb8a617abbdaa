#include "slipfit/pipeline/point_data.h"

#include "slipfit/pipeline/ply_scalar.h"

#include <pcl/common/io.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace slipfit::pipeline {

void PointData::setField(PointField field) {
  for (auto& f : fields)
    if (f.name == field.name) {
      f = std::move(field);
      return;
    }
  fields.push_back(std::move(field));
}

PointData sampledPointData(const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& normals,
                           bool with_normals) {
  PointData out;
  out.cloud->resize(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    auto& q = (*out.cloud)[static_cast<std::size_t>(i)];
    q.getVector3fMap() = points.col(i).cast<float>();
    if (with_normals)
      q.getNormalVector3fMap() = normals.col(i).cast<float>();
    else
      q.getNormalVector3fMap().setConstant(std::numeric_limits<float>::quiet_NaN());
    q.curvature = 0.0f;
  }
  out.has_normals = with_normals;
  return out;
}

const PointField* PointData::field(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

std::vector<double> PointData::numericField(const std::string& name) const {
  std::vector<double> out;
  if (const PointField* f = field(name)) {
    std::visit(
        [&](const auto& v) {
          out.reserve(v.size());
          for (const auto x : v)
            out.push_back(static_cast<double>(x));
        },
        f->values);
    return out;
  }
  for (const auto& f : extra.fields) {
    const std::optional<ply::Scalar> scalar = ply::scalarOfDatatype(f.datatype);
    if (f.name != name || f.count != 1 || !scalar)
      continue;
    out.resize(extra.width);
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = ply::decode(*scalar, extra.data.data() + i * extra.point_step + f.offset);
    return out;
  }
  return out;
}

const std::vector<SlippageType>* PointData::localSlippage() const {
  const PointField* f = field(kSlippageTypeField);
  return f ? std::get_if<std::vector<SlippageType>>(&f->values) : nullptr;
}

std::string dataBitsText(unsigned bits) {
  std::string s;
  auto add = [&](unsigned bit, const char* name) {
    if (bits & bit)
      s += (s.empty() ? "" : ", ") + std::string(name);
  };
  add(kPoints, "points");
  add(kNormals, "normals");
  add(kNeighborhoods, "neighborhoods");
  add(kLocalSlippage,
      "the local slippage (slippage_type, from slippage_classification with mode: local)");
  return s;
}

}  // namespace slipfit::pipeline

namespace slipfit::pipeline {

void PointData::keepOnly(const std::vector<char>& keep) {
  const std::size_t n = size();
  pcl::Indices kept;
  kept.reserve(static_cast<std::size_t>(
      std::count_if(keep.begin(), keep.begin() + n, [](char k) { return k != 0; })));
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i])
      kept.push_back(static_cast<pcl::index_t>(i));
  keepOnly(kept);
}

void PointData::keepOnly(const pcl::Indices& kept) {
  const std::size_t n = size();
  const std::size_t m = kept.size();
  if (m == n)
    return;

  // Compacted vectors give their memory back (shrink_to_fit): after a subsample the full cloud's
  // worth of capacity would otherwise stay allocated through every later stage.
  auto compact = [&](auto& vec) {
    for (std::size_t j = 0; j < m; ++j)
      vec[j] = vec[static_cast<std::size_t>(kept[j])];  // kept[j] >= j: ascending
    vec.resize(m);
    vec.shrink_to_fit();
  };
  if (cloud.use_count() == 1 && 2 * m >= n) {
    // Ours alone and at least half kept: compacted in place, as the fields are, with no second
    // buffer to fault in and no first one to give back; the capacity of the dropped points (at
    // most half) stays reserved, as in a vector's growth.
    auto& points = cloud->points;
    for (std::size_t j = 0; j < m; ++j)
      points[j] = points[static_cast<std::size_t>(kept[j])];  // kept[j] >= j: ascending
    points.resize(m);
    cloud->width = static_cast<std::uint32_t>(m);
    cloud->height = 1;
  } else {
    // A new cloud: the old one may be shared (the subsample stage keeps the full one), or most of
    // its memory is to be given back. PCL's copy by indices, as a PCL filter's user would call it.
    auto copy = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    pcl::copyPointCloud(*cloud, kept, *copy);
    copy->is_dense = cloud->is_dense;
    cloud = std::move(copy);
  }
  for (auto& f : fields)
    std::visit(compact, f.values);
  if (pixels.size() == n)
    compact(pixels);
  if (extra.width == n && extra.point_step > 0) {
    for (std::size_t j = 0; j < m; ++j)
      std::copy_n(extra.data.begin() + static_cast<std::ptrdiff_t>(kept[j]) * extra.point_step,
                  extra.point_step, extra.data.begin() + j * extra.point_step);
    extra.width = static_cast<std::uint32_t>(m);
    extra.row_step = extra.point_step * extra.width;
    extra.data.resize(static_cast<std::size_t>(extra.row_step));
    extra.data.shrink_to_fit();
  } else if (extra.width == n) {
    extra.width = static_cast<std::uint32_t>(m);
  }
  if (neighborhoods) {
    std::vector<pcl::index_t> new_index(n, -1);
    for (std::size_t j = 0; j < m; ++j)
      new_index[static_cast<std::size_t>(kept[j])] = static_cast<pcl::index_t>(j);
    auto remapped = std::make_shared<Neighborhoods>();
    remapped->reserve(m, neighborhoods->entries());
    pcl::Indices ind;
    std::vector<float> dist;
    for (const auto i : kept) {
      ind.clear();
      dist.clear();
      const NeighborView v = (*neighborhoods)[static_cast<std::size_t>(i)];
      for (std::size_t k = 0; k < v.size(); ++k)
        if (new_index[v[k]] >= 0) {
          ind.push_back(new_index[v[k]]);
          dist.push_back(v.sqr_distances[k]);
        }
      remapped->append(ind.data(), dist.data(), ind.size());
    }
    neighborhoods = remapped;
  }
}

void PointData::expandToFull(bool stage_fields) {
  if (!full)
    return;
  PointData out = std::move(*full);
  const std::size_t n = out.size();
  if (has_normals) {
    for (std::size_t i = 0; i < n; ++i) {
      if (representative[i] < 0)
        continue;  // a non-finite input point keeps its NaN normal
      const auto& r = (*cloud)[static_cast<std::size_t>(representative[i])];
      auto& p = (*out.cloud)[i];
      p.getNormalVector3fMap() = r.getNormalVector3fMap();
      p.curvature = r.curvature;
    }
    out.has_normals = true;
    out.has_curvature = has_curvature;
  }
  for (const auto& f : stage_fields ? fields : std::vector<PointField>{}) {
    PointField expanded{f.name, {}};
    std::visit(
        [&](const auto& v) {
          std::decay_t<decltype(v)> w(n);
          for (std::size_t i = 0; i < n; ++i)
            if (representative[i] >= 0)
              w[i] = v[static_cast<std::size_t>(representative[i])];
          expanded.values = std::move(w);
        },
        f.values);
    out.setField(std::move(expanded));
  }
  *this = std::move(out);
}

}  // namespace slipfit::pipeline
