#include "slipfit/pipeline/point_data.h"

#include <algorithm>

namespace slipfit::pipeline {

void PointData::setField(PointField field) {
  for (auto& f : fields)
    if (f.name == field.name) {
      f = std::move(field);
      return;
    }
  fields.push_back(std::move(field));
}

const PointField* PointData::field(const std::string& name) const {
  for (const auto& f : fields)
    if (f.name == name)
      return &f;
  return nullptr;
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
  return s;
}

}  // namespace slipfit::pipeline

namespace slipfit::pipeline {

void PointData::keepOnly(const std::vector<char>& keep) {
  const std::size_t n = size();
  std::vector<pcl::index_t> new_index(n, -1);
  std::size_t m = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i])
      new_index[i] = static_cast<pcl::index_t>(m++);
  if (m == n)
    return;

  auto compact = [&](auto& vec) {
    std::size_t j = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i])
        vec[j++] = vec[i];
    vec.resize(m);
  };
  compact(cloud->points);
  cloud->width = static_cast<std::uint32_t>(m);
  cloud->height = 1;
  for (auto& f : fields)
    std::visit(compact, f.values);
  if (extra.width == n && extra.point_step > 0) {
    std::size_t j = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) {
        std::copy_n(extra.data.begin() + i * extra.point_step, extra.point_step,
                    extra.data.begin() + j * extra.point_step);
        ++j;
      }
    extra.width = static_cast<std::uint32_t>(m);
    extra.row_step = extra.point_step * extra.width;
    extra.data.resize(static_cast<std::size_t>(extra.row_step));
  } else if (extra.width == n) {
    extra.width = static_cast<std::uint32_t>(m);
  }
  if (neighborhoods) {
    auto remapped = std::make_shared<Neighborhoods>();
    remapped->reserve(m, neighborhoods->entries());
    pcl::Indices ind;
    std::vector<float> dist;
    for (std::size_t i = 0; i < n; ++i) {
      if (!keep[i])
        continue;
      ind.clear();
      dist.clear();
      const NeighborView v = (*neighborhoods)[i];
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

}  // namespace slipfit::pipeline
