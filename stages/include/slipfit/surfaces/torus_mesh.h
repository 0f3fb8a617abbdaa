#pragma once
/// \file A stitched, outward-oriented OpenMesh quad mesh of the whole torus, with analytic vertex
/// normals, and the naive variant (four separate quarter meshes) for comparison.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/surfaces/surface_mesh.h"
#include "slipfit/surfaces/torus.h"

#include <Eigen/Geometry>

#include <array>
#include <string_view>

namespace slipfit {

/// How mesh vertices (or samples) are spaced along α and β.
enum class TorusSpacing {
  angle,     ///< uniform in α and β
  parameter  ///< uniform in the quarter patches' parameters u, v (needs even resolutions)
};
constexpr std::array<std::pair<TorusSpacing, std::string_view>, 2> kTorusSpacingNames{{
    {TorusSpacing::angle, "angle"},
    {TorusSpacing::parameter, "parameter"},
}};

struct TorusMeshParameters {
  int n_alpha = 48;  ///< vertices around the tube, >= 3 (even for parameter spacing)
  int n_beta = 96;   ///< vertices around the axis, >= 3 (even for parameter spacing)
  TorusSpacing spacing = TorusSpacing::angle;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.n_alpha, parameter("mesh_alpha", "Mesh vertices around the tube.")
                            .in("vertices")
                            .between(3, 100000));
    visit(
        self.n_beta,
        parameter("mesh_beta", "Mesh vertices around the axis.").in("vertices").between(3, 100000));
    visit(self.spacing,
          parameter("mesh_spacing",
                    "angle: vertices uniform in (α, β); parameter: uniform in the quarters' (u, v) "
                    "(even resolutions)."),
          kTorusSpacingNames);
  }

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// The angles of vertex i of n around a circle for a spacing (seam vertices appear once).
double torusGridAngle(int i, int n, TorusSpacing spacing);

/// The whole torus: n_alpha × n_beta vertices evaluated on the Bézier quarters, one quad per grid
/// cell with wrap-around (V = F = n_alpha n_beta, E = 2V, χ = 0), faces ordered so that their
/// normals point out of the tube, vertex normals the analytic ones. \a pose maps the torus frame
/// (axis z, centre 0) to the world.
SurfaceMesh torusMesh(const TorusShape& torus, const TorusMeshParameters& parameters,
                      const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());

/// Four separate quarter meshes of (n_alpha/2 + 1) × (n_beta/2 + 1) vertices each, parameter
/// spaced, with duplicated seam vertices and face-averaged vertex normals: what a per-patch
/// tessellation gives, kept to show the seams and shading cusps that torusMesh avoids.
SurfaceMesh torusMeshNaive(const TorusShape& torus, const TorusMeshParameters& parameters,
                           const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());

}  // namespace slipfit
