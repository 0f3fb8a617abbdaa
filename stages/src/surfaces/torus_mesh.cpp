#include "slipfit/surfaces/torus_mesh.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"

#include <cmath>
#include <string>
#include <vector>

namespace slipfit {

namespace {

OpenMesh::Vec3d toOm(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
}  // namespace

void TorusMeshParameters::validate() const {
  validateDeclared(*this, "torus mesh");
  if (spacing == TorusSpacing::parameter && (n_alpha % 2 || n_beta % 2))
    throw InvalidParameterError(
        "torus mesh: parameter spacing needs even resolutions (each half "
        "circle is one patch), got " +
        std::to_string(n_alpha) + " × " + std::to_string(n_beta));
}

double torusGridAngle(int i, int n, TorusSpacing spacing) {
  if (spacing == TorusSpacing::angle)
    return 2.0 * kPi * i / n;
  const int half = n / 2;
  // First half: quarter parameter u = i/half on [0, π]; second half: the reflected patch, whose
  // parameter runs from 1 back to 0 while α goes from π to 2π.
  if (i < half)
    return quarterAngle(static_cast<double>(i) / half);
  return 2.0 * kPi - quarterAngle(1.0 - static_cast<double>(i - half) / half);
}

SurfaceMesh torusMesh(const TorusShape& torus, const TorusMeshParameters& p,
                      const Eigen::Isometry3d& pose) {
  torus.validate();
  p.validate();
  const TorusBezier bezier(torus);
  SurfaceMesh mesh;
  const auto na = static_cast<std::size_t>(p.n_alpha), nb = static_cast<std::size_t>(p.n_beta);
  mesh.reserve(na * nb, 2 * na * nb, na * nb);
  std::vector<SurfaceMesh::VertexHandle> v(na * nb);
  for (std::size_t i = 0; i < na; ++i) {
    const double a = torusGridAngle(static_cast<int>(i), p.n_alpha, p.spacing);
    for (std::size_t j = 0; j < nb; ++j) {
      const double b = torusGridAngle(static_cast<int>(j), p.n_beta, p.spacing);
      const SurfacePoint s = bezier.evaluate(a, b);
      v[i * nb + j] = mesh.add_vertex(toOm(pose * s.position));
      mesh.set_normal(v[i * nb + j], toOm(pose.linear() * s.normal));
    }
  }
  // (i, j) → (i, j+1) → (i+1, j+1) → (i+1, j) runs against Sα × Sβ, which points into the tube.
  for (std::size_t i = 0; i < na; ++i)
    for (std::size_t j = 0; j < nb; ++j) {
      const std::size_t i1 = (i + 1) % na, j1 = (j + 1) % nb;
      mesh.add_face(v[i * nb + j], v[i * nb + j1], v[i1 * nb + j1], v[i1 * nb + j]);
    }
  mesh.update_face_normals();
  return mesh;
}

SurfaceMesh torusMeshNaive(const TorusShape& torus, const TorusMeshParameters& p,
                           const Eigen::Isometry3d& pose) {
  torus.validate();
  TorusMeshParameters q = p;
  q.spacing = TorusSpacing::parameter;
  q.validate();
  SurfaceMesh mesh;
  const int mu = p.n_alpha / 2, mv = p.n_beta / 2;
  for (int quarter = 0; quarter < 4; ++quarter) {
    const RationalBezierPatch patch = torusQuarterPatch(torus, quarter);
    std::vector<SurfaceMesh::VertexHandle> v(static_cast<std::size_t>((mu + 1) * (mv + 1)));
    for (int i = 0; i <= mu; ++i)
      for (int j = 0; j <= mv; ++j)
        v[i * (mv + 1) + j] =
            mesh.add_vertex(toOm(pose * patch.evaluate(double(i) / mu, double(j) / mv).position));
    // Reflected quarters reverse the parameter orientation.
    const bool flip = ((quarter & 1) + ((quarter >> 1) & 1)) % 2 == 1;
    for (int i = 0; i < mu; ++i)
      for (int j = 0; j < mv; ++j) {
        auto a = v[i * (mv + 1) + j], b = v[i * (mv + 1) + j + 1],
             c = v[(i + 1) * (mv + 1) + j + 1], d = v[(i + 1) * (mv + 1) + j];
        if (flip)
          mesh.add_face(a, d, c, b);
        else
          mesh.add_face(a, b, c, d);
      }
  }
  mesh.update_normals();
  return mesh;
}

}  // namespace slipfit
