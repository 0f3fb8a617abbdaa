#pragma once
/// \file Thin walls: a wall about as thick as the spacing puts both of its faces (two parallel
/// sheets) in every neighborhood. Used by phase 1 (the noise on each point's own sheet) and
/// phase 3 (a free seed's own sheet of its 2-ring).

#include <pcl/types.h>

#include <Eigen/Core>

#include <vector>

namespace slipfit::phases {

/// The points of the neighborhood \a idx on point \a i's own sheet when it holds two sheets of a
/// thin wall; otherwise \a idx itself. \a axes: the neighborhood's principal axes (columns);
/// \a radius: its radius.
std::vector<pcl::index_t> ownSheet(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                   const std::vector<pcl::index_t>& idx, pcl::index_t i,
                                   const Eigen::Matrix3d& axes, double radius);

/// The points of \a candidates on the seed's own sheet of a thin wall: ordered by their offset
/// along the seed's \a normal, the run around the seed that no gap wider than \a gap interrupts.
/// Empty when no such gap divides the candidates (one surface, or faces meeting at a crease:
/// their offsets run on without a gap).
std::vector<int> seedSheet(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                           const Eigen::Vector3d& normal, int seed,
                           const std::vector<int>& candidates, double gap);

}  // namespace slipfit::phases
