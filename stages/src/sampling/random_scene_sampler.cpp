#include "slipfit/sampling/random_scene_sampler.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "slipfit/sampling/random_vector.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

namespace slipfit {

namespace {

constexpr std::size_t kMinPerShape = 500, kMaxPerShape = 50000;

/// One shape in its local frame (axis z, centred near the origin) with its sampling ranges.
struct LocalShape {
  PrimitiveSamplingParameters sampling;
  double radius = 1.0;  ///< radius of a ball around the origin holding the shape
};

LocalShape localShape(PrimitiveType type, double size, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  LocalShape s;
  auto& p = s.sampling;
  switch (type) {
    case PrimitiveType::plane:
      p.primitive = Plane{Eigen::Vector3d::UnitZ(), 0.0};
      p.extent = 0.5 * size;
      s.radius = 0.71 * size;
      break;
    case PrimitiveType::sphere:
      p.primitive = Sphere{Eigen::Vector3d::Zero(), 0.5 * size};
      s.radius = 0.5 * size;
      break;
    case PrimitiveType::cylinder: {
      const double r = size * (0.1 + 0.3 * u(rng));
      p.primitive = Cylinder{Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, 0, -0.5 * size), r};
      p.extent = size;
      s.radius = std::hypot(0.5 * size, r);
      break;
    }
    case PrimitiveType::cone: {
      const double theta = (15.0 + 45.0 * u(rng)) * kPi / 180.0;
      // A band of heights [h0, h1] from the apex, its widest radius at most size / 2.
      const double h1 = std::min(size, 0.5 * size / std::tan(theta));
      p.primitive = Cone{Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, 0, -0.5 * h1), theta};
      p.extent_min = 0.25 * h1;
      p.extent = h1;
      s.radius = std::hypot(0.5 * h1, h1 * std::tan(theta));
      break;
    }
    case PrimitiveType::torus: {
      const double major = 0.35 * size;
      p.primitive = Torus{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), major,
                          major * (0.15 + 0.35 * u(rng))};
      s.radius = 0.6 * size;
      break;
    }
  }
  return s;
}

Eigen::Matrix3d randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Vector4d w = randomVector<4>(g, rng);
  Eigen::Quaterniond q(w(0), w(1), w(2), w(3));
  q.normalize();
  return q.toRotationMatrix();
}

}  // namespace

void RandomSceneParameters::validate() const {
  if (shapes < 1 || shapes > 10000)
    throw InvalidParameterError("random scene: shapes must be in [1, 10000]");
  if (points < 100)
    throw InvalidParameterError("random scene: points must be at least 100");
  if (!(size > 0.0 && std::isfinite(size)))
    throw InvalidParameterError("random scene: size must be > 0");
  if (!(noise >= 0.0 && noise <= 0.05))
    throw InvalidParameterError("random scene: noise must be in [0, 0.05]");
  if (!(outlier_fraction >= 0.0 && outlier_fraction <= 1.0))
    throw InvalidParameterError("random scene: outliers must be in [0, 1]");
}

Primitive transformed(const Primitive& primitive, const Eigen::Matrix3d& rotation,
                      const Eigen::Vector3d& translation) {
  return std::visit(
      [&](auto s) -> Primitive {
        using T = decltype(s);
        if constexpr (std::is_same_v<T, Plane>) {
          s.normal = rotation * s.normal;
          s.d += s.normal.dot(translation);
        } else if constexpr (std::is_same_v<T, Sphere>) {
          s.center = rotation * s.center + translation;
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          s.axis = rotation * s.axis;
          s.point = rotation * s.point + translation;
        } else if constexpr (std::is_same_v<T, Cone>) {
          s.axis = rotation * s.axis;
          s.apex = rotation * s.apex + translation;
        } else {
          s.axis = rotation * s.axis;
          s.center = rotation * s.center + translation;
        }
        return s;
      },
      primitive);
}

void sampleRandomScene(const RandomSceneParameters& parameters, Eigen::Matrix3Xd& points,
                       Eigen::Matrix3Xd& normals, std::vector<std::int32_t>& labels,
                       std::vector<Primitive>& truth) {
  parameters.validate();
  std::mt19937_64 rng(parameters.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const PrimitiveType kTypes[] = {PrimitiveType::plane, PrimitiveType::sphere,
                                  PrimitiveType::cylinder, PrimitiveType::cone,
                                  PrimitiveType::torus};
  std::discrete_distribution<int> pick({31, 10, 16, 7, 11});

  // Pieces: a primitive in its local frame, its pose, its share of the points.
  struct Piece {
    PrimitiveSamplingParameters sampling;
    Eigen::Matrix3d rotation;
    Eigen::Vector3d translation;
    double weight;  // log-uniform density draw
    bool quarter_fillet = false;
  };
  std::vector<Piece> pieces;
  std::vector<double> sizes;
  // Shapes are placed on a square grid of cells as wide as the largest shape, in random order;
  // a fifth of them are pulled onto the previous shape so that they touch or cut it.
  const double largest = 20.0 * parameters.size;
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(double(parameters.shapes))));
  std::size_t cell = 0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  double previous_radius = 0.0;
  while (pieces.size() < parameters.shapes) {
    const double size = parameters.size * std::exp(std::log(20.0) * u(rng));
    sizes.push_back(size);
    Eigen::Vector3d centre(largest * 1.2 * double(cell % side), largest * 1.2 * double(cell / side),
                           0.0);
    centre += 0.2 * largest * (randomVector<3>(u, rng) - Eigen::Vector3d::Constant(0.5));
    ++cell;
    const Eigen::Matrix3d rotation = randomRotation(rng);
    const double weight = std::exp(std::log(100.0) * u(rng));
    const bool bracket = pieces.size() + 3 <= parameters.shapes && u(rng) < 0.1;
    if (bracket) {
      // L-bracket: plane z = 0 for x ∈ [−L, 0], a quarter cylinder of radius ρ about the y axis
      // through (0, ·, ρ) tangent to both, the plane x = ρ for z ∈ [ρ, ρ + L]; y ∈ [−W, W].
      const double L = 0.5 * size, W = 0.5 * size, rho = size * (0.1 + 0.2 * u(rng));
      Piece a{{}, rotation, centre + rotation * Eigen::Vector3d(-0.5 * L, 0, 0), weight};
      a.sampling.primitive = Plane{Eigen::Vector3d::UnitZ(), 0.0};
      a.sampling.extent = 0.5 * L;  // square of side L (y extent L as well)
      Piece f{{}, rotation, centre, weight, true};
      f.sampling.primitive =
          Cylinder{Eigen::Vector3d::UnitY(), Eigen::Vector3d(0, -0.5 * L, rho), rho};
      f.sampling.extent = L;
      Piece b{{},
              rotation * Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix(),
              centre + rotation * Eigen::Vector3d(rho, 0, rho + 0.5 * L),
              weight};
      b.sampling.primitive = Plane{Eigen::Vector3d::UnitZ(), 0.0};
      b.sampling.extent = 0.5 * L;
      (void)W;
      pieces.push_back(a);
      pieces.push_back(f);
      pieces.push_back(b);
      previous = centre;
      previous_radius = L + rho;
      continue;
    }
    const PrimitiveType type = kTypes[pick(rng)];
    LocalShape shape = localShape(type, size, rng);
    if (!pieces.empty() && u(rng) < 0.2) {
      // Touch or cut the previous shape: centres at 0.7–1.0 × the sum of the radii.
      const Eigen::Vector3d dir = randomVector<3>(gauss, rng).normalized();
      centre = previous + (0.7 + 0.3 * u(rng)) * (previous_radius + shape.radius) * dir;
    }
    pieces.push_back({shape.sampling, rotation, centre, weight});
    previous = centre;
    previous_radius = shape.radius;
  }

  // Points per piece: proportional to the density draw, clamped to [500, 50,000].
  double total_weight = 0.0;
  for (const Piece& p : pieces)
    total_weight += p.weight;
  std::vector<std::size_t> counts;
  for (const Piece& p : pieces)
    counts.push_back(std::clamp<std::size_t>(
        static_cast<std::size_t>(double(parameters.points) * p.weight / total_weight), kMinPerShape,
        kMaxPerShape));

  std::sort(sizes.begin(), sizes.end());
  const double sigma = parameters.noise * sizes[sizes.size() / 2];
  std::size_t total = 0;
  for (std::size_t c : counts)
    total += c;
  const auto outliers =
      static_cast<std::size_t>(std::llround(parameters.outlier_fraction * double(total)));
  points.resize(3, static_cast<Eigen::Index>(total + outliers));
  normals.resize(3, points.cols());
  labels.assign(static_cast<std::size_t>(points.cols()), -1);
  truth.clear();
  Eigen::Index at = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    Piece& piece = pieces[k];
    piece.sampling.points = counts[k];
    piece.sampling.seed = rng();
    if (piece.quarter_fillet) {
      // From −z to +x about the y axis: samplePrimitive's angle runs from u = axis.unitOrthogonal()
      // = −x towards v = axis × u = +z, so +x is φ = π and −z is φ = 3π/2.
      piece.sampling.angle_min = kPi;
      piece.sampling.angle_max = 1.5 * kPi;
    }
    Eigen::Matrix3Xd x, n;
    samplePrimitive(piece.sampling, x, n);
    for (Eigen::Index i = 0; i < x.cols(); ++i, ++at) {
      points.col(at) = piece.rotation * x.col(i) + piece.translation;
      if (sigma > 0.0)
        points.col(at) += sigma * randomVector<3>(gauss, rng);
      normals.col(at) = piece.rotation * n.col(i);
      labels[static_cast<std::size_t>(at)] = static_cast<std::int32_t>(k);
    }
    truth.push_back(transformed(piece.sampling.primitive, piece.rotation, piece.translation));
  }
  if (outliers > 0) {
    const Eigen::Vector3d lo = points.leftCols(at).rowwise().minCoeff();
    const Eigen::Vector3d hi = points.leftCols(at).rowwise().maxCoeff();
    for (; at < points.cols(); ++at) {
      points.col(at) = lo + (hi - lo).cwiseProduct(randomVector<3>(u, rng));
      const Eigen::Vector3d d = randomVector<3>(gauss, rng);
      normals.col(at) = d.norm() > 0.0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::UnitZ();
    }
  }
}

}  // namespace slipfit
