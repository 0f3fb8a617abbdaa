#pragma once
/// \file Orientation (sign) of unoriented normals: towards a viewpoint, like reference normals, or
/// globally consistent by propagation over a minimum spanning tree (Hoppe et al., SIGGRAPH 1992).
/// Kernels on 3×N views; a NaN normal is left alone and never propagates.

#include "slipfit/core/cloud_maps.h"
#include "slipfit/neighborhoods/neighborhoods.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace slipfit {

/// How the sign of estimated normals is chosen.
enum class NormalOrientation {
  viewpoint,   ///< each normal faces the viewpoint: (v − p)·n ≥ 0
  reference,   ///< each normal agrees in sign with a reference normal (e.g. the input's own)
  consistent,  ///< neighbors agree, propagated over a minimum spanning tree of the kNN graph
  /// each normal faces the input cloud's sensor_origin_ (PCL's convention: a PCD's VIEWPOINT sets
  /// it, and pcl::NormalEstimation orients towards it unless given a viewpoint)
  sensor
};

constexpr std::array<std::pair<NormalOrientation, std::string_view>, 4> kNormalOrientationNames{{
    {NormalOrientation::viewpoint, "viewpoint"},
    {NormalOrientation::reference, "reference"},
    {NormalOrientation::consistent, "consistent"},
    {NormalOrientation::sensor, "sensor"},
}};

/// Flips normals so that they face \a viewpoint. Returns how many were flipped.
std::size_t orientTowardsViewpoint(const ConstCoords3Map& points, Coords3Map normals,
                                   const Eigen::Vector3f& viewpoint);

/// Flips normals whose dot product with the matching column of \a reference is negative.
/// A NaN or zero reference leaves the normal as it is. Returns how many were flipped.
std::size_t orientLikeReference(Coords3Map normals, const ConstCoords3Map& reference);

struct ConsistentOrientationReport {
  std::size_t flipped = 0;     ///< normals whose sign changed
  std::size_t components = 0;  ///< connected components of the neighbor graph (each seeded once)
  std::size_t oriented = 0;    ///< normals reached (finite normals)
};

/// Globally consistent orientation (Hoppe et al. 1992).
///
/// The graph is the symmetrised neighbor graph; edge (i, j) costs 1 − |nᵢ·nⱼ|. In each connected
/// component a seed is oriented, then Prim's minimum spanning tree propagates the sign along the
/// smoothest edges first, flipping nⱼ when nᵢ·nⱼ < 0. Without \a viewpoint the seed is the point
/// whose normal is most nearly radial from the component's centroid, |(p − c)·n| largest, oriented
/// away from the centroid: outward on a closed surface. With \a viewpoint the seed is the point
/// whose normal is most nearly along its line of sight, nearer points preferred, oriented towards
/// the viewer: right for open scans, and outward on closed surfaces seen from outside.
/// Deterministic.
/// \param points 3×N coordinates; \param normals 3×N normals, reoriented in place;
/// \param graph neighbor lists of the same N points.
ConsistentOrientationReport orientConsistently(
    const ConstCoords3Map& points, Coords3Map normals, const Neighborhoods& graph,
    const std::optional<Eigen::Vector3f>& viewpoint = {});

}  // namespace slipfit
