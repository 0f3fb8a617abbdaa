#include "slipfit/sampling/kinematic_scene_sampler.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/kinematic_sampler.h"
#include "slipfit/sampling/random_vector.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <utility>

namespace slipfit {

namespace {

constexpr double kPlateHalfSide = 1.2;
constexpr int kMeridianVertices = 160, kSectionVertices = 180;

using Rng = std::mt19937_64;
using Sampler = std::function<void(std::size_t, Rng&, Eigen::Matrix3Xd&, Eigen::Matrix3Xd&)>;

/// One true surface of the scene: what it is, its area and how to sample it.
struct Piece {
  SurfaceTruth truth;
  double area = 0.0;
  Sampler sample;
};

/// Where a part stands on the plate, and the plate it hides: the points within radius(φ) of
/// `at`, φ the angle from x.
struct Footprint {
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
  std::function<double(double)> radius = [](double) { return 0.0; };
  double area = 0.0;

  bool hides(const Eigen::Vector2d& q) const {
    const Eigen::Vector2d d = q - at;
    return d.norm() < radius(std::atan2(d.y(), d.x()));
  }
};

Footprint round(const Eigen::Vector2d& at, double radius) {
  return {at, [radius](double) { return radius; }, kPi * radius * radius};
}

double uniform(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Piece kinematicPiece(KinematicSurface s, MotionStretch stretch) {
  Piece p;
  p.area = kinematicArea(s, stretch);
  p.sample = [s, stretch](std::size_t n, Rng& rng, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& nn) {
    sampleKinematicSurface(s, stretch, n, rng, x, nn);
  };
  p.truth = std::move(s);
  return p;
}

/// The flat top of a part at height \a h over \a foot: the points within radius \a inside(φ) of
/// the axis (rejection in the disc of radius \a outer).
Piece topFace(const Eigen::Vector2d& foot, double h, double outer, double area,
              std::function<double(double)> inside) {
  Piece p;
  p.truth = Primitive{Plane{Eigen::Vector3d::UnitZ(), h}};
  p.area = area;
  p.sample = [foot, h, outer, inside](std::size_t n, Rng& rng, Eigen::Matrix3Xd& x,
                                      Eigen::Matrix3Xd& nn) {
    x.resize(3, static_cast<Eigen::Index>(n));
    nn.resize(3, static_cast<Eigen::Index>(n));
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      Eigen::Vector2d q;
      do {
        q = Eigen::Vector2d(uniform(rng, -outer, outer), uniform(rng, -outer, outer));
      } while (q.norm() > outer || q.norm() > inside(std::atan2(q.y(), q.x())));
      x.col(i) = Eigen::Vector3d(foot.x() + q.x(), foot.y() + q.y(), h);
      nn.col(i) = Eigen::Vector3d::UnitZ();
    }
  };
  return p;
}

Piece disc(const Eigen::Vector2d& foot, double h, double radius) {
  return topFace(foot, h, radius, kPi * radius * radius, [radius](double) { return radius; });
}

KinematicSurface standing(KinematicType type, const Eigen::Vector2d& foot) {
  KinematicSurface s;
  s.type = type;
  s.axis = Eigen::Vector3d::UnitZ();
  s.point = Eigen::Vector3d(foot.x(), foot.y(), 0.0);
  s.reference = Eigen::Vector3d::UnitX();
  return s;
}

/// A turned part: ρ(h) = R (1 + Σₖ aₖ sin(k π h / H + ψₖ)), k = 1..3, kept at least 0.45 R.
double turnedPart(const Eigen::Vector2d& foot, Rng& rng, std::vector<Piece>& pieces,
                  Footprint& print) {
  const double r = uniform(rng, 0.18, 0.26), height = uniform(rng, 0.5, 0.8);
  double a[3], psi[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = uniform(rng, -0.25, 0.25) / (k + 1);
    psi[k] = uniform(rng, 0.0, 2.0 * kPi);
  }
  KinematicSurface s = standing(KinematicType::revolution, foot);
  for (int i = 0; i <= kMeridianVertices; ++i) {
    const double h = height * i / kMeridianVertices;
    double rho = 1.0;
    for (int k = 0; k < 3; ++k)
      rho += a[k] * std::sin((k + 1) * kPi * h / height + psi[k]);
    s.profile.vertices.emplace_back(h, r * std::max(rho, 0.45));
  }
  const double top = s.profile.vertices.back().y(), bottom = s.profile.vertices.front().y();
  double widest = 0.0;
  for (const Eigen::Vector2d& v : s.profile.vertices)
    widest = std::max(widest, v.y());
  pieces.push_back(kinematicPiece(s, {0.0, 2.0 * kPi}));
  pieces.push_back(disc(foot, height, top));
  print = round(foot, bottom);
  return std::max(height, 2.0 * widest);
}

/// An extruded section r(φ) = R (1 + Σₖ bₖ cos(k φ + ψₖ)), k = 2..4, counter-clockwise.
double extrudedPart(const Eigen::Vector2d& foot, Rng& rng, std::vector<Piece>& pieces,
                    Footprint& print) {
  const double r = uniform(rng, 0.18, 0.26), height = uniform(rng, 0.3, 0.6);
  double b[3], psi[3];
  for (int k = 0; k < 3; ++k) {
    b[k] = (k % 2 ? -1.0 : 1.0) * uniform(rng, 0.04, 0.12);
    psi[k] = uniform(rng, 0.0, 2.0 * kPi);
  }
  const auto section = [=](double phi) {
    double rho = 1.0;
    for (int k = 0; k < 3; ++k)
      rho += b[k] * std::cos((k + 2) * phi + psi[k]);
    return r * rho;
  };
  KinematicSurface s = standing(KinematicType::extrusion, foot);
  s.profile.closed = true;
  double outer = 0.0, area = 0.0;
  for (int j = 0; j < kSectionVertices; ++j) {
    const double phi = 2.0 * kPi * j / kSectionVertices;
    const double rho = section(phi);
    outer = std::max(outer, rho);
    s.profile.vertices.emplace_back(rho * std::cos(phi), rho * std::sin(phi));
  }
  for (int j = 0; j < kSectionVertices; ++j) {  // the polygon's area (shoelace)
    const Eigen::Vector2d& p = s.profile.vertices[static_cast<std::size_t>(j)];
    const Eigen::Vector2d& q =
        s.profile.vertices[static_cast<std::size_t>((j + 1) % kSectionVertices)];
    area += 0.5 * (p.x() * q.y() - q.x() * p.y());
  }
  pieces.push_back(kinematicPiece(s, {0.0, height}));
  pieces.push_back(topFace(foot, height, outer, area, section));
  print = {foot, section, area};
  return std::max(height, 2.0 * outer);
}

/// A threaded rod: core radius R, a V-thread of depth 0.35 P on a period P = 2π pitch (flat roots
/// and crests of 0.3 P and 0.2 P).
double threadedRod(const Eigen::Vector2d& foot, Rng& rng, std::vector<Piece>& pieces,
                   Footprint& print) {
  const double r = uniform(rng, 0.06, 0.1), height = uniform(rng, 0.5, 0.8);
  const double period = uniform(rng, 0.04, 0.07), depth = 0.35 * period;
  KinematicSurface s = standing(KinematicType::helix, foot);
  s.pitch = period / (2.0 * kPi);
  for (const auto& [u, rise] :
       {std::pair{0.0, 0.0}, {0.15, 0.0}, {0.4, 1.0}, {0.6, 1.0}, {0.85, 0.0}, {1.0, 0.0}})
    s.profile.vertices.emplace_back(u * period, r + rise * depth);
  pieces.push_back(kinematicPiece(s, {0.0, height}));
  pieces.push_back(disc(foot, height, r));
  print = round(foot, r + depth);
  return std::max(height, 2.0 * (r + depth));
}

double cylinderPart(const Eigen::Vector2d& foot, Rng& rng, std::vector<Piece>& pieces,
                    Footprint& print) {
  const double r = uniform(rng, 0.1, 0.2), height = uniform(rng, 0.3, 0.6);
  Piece side;
  side.truth =
      Primitive{Cylinder{Eigen::Vector3d::UnitZ(), Eigen::Vector3d(foot.x(), foot.y(), 0.0), r}};
  side.area = 2.0 * kPi * r * height;
  side.sample = [foot, r, height](std::size_t n, Rng& rng, Eigen::Matrix3Xd& x,
                                  Eigen::Matrix3Xd& nn) {
    x.resize(3, static_cast<Eigen::Index>(n));
    nn.resize(3, static_cast<Eigen::Index>(n));
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const double phi = uniform(rng, 0.0, 2.0 * kPi), h = uniform(rng, 0.0, height);
      nn.col(i) = Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0);
      x.col(i) = Eigen::Vector3d(foot.x(), foot.y(), h) + r * nn.col(i);
    }
  };
  pieces.push_back(std::move(side));
  pieces.push_back(disc(foot, height, r));
  print = round(foot, r);
  return std::max(height, 2.0 * r);
}

double spherePart(const Eigen::Vector2d& foot, Rng& rng, std::vector<Piece>& pieces,
                  Footprint& print) {
  const double r = uniform(rng, 0.12, 0.2);
  const Eigen::Vector3d center(foot.x(), foot.y(), r);
  Piece p;
  p.truth = Primitive{Sphere{center, r}};
  p.area = 4.0 * kPi * r * r;
  p.sample = [center, r](std::size_t n, Rng& rng, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& nn) {
    x.resize(3, static_cast<Eigen::Index>(n));
    nn.resize(3, static_cast<Eigen::Index>(n));
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      Eigen::Vector3d d;
      do {
        d = randomVector<3>(gauss, rng);
      } while (!(d.norm() > 1e-12));
      nn.col(i) = d.normalized();
      x.col(i) = center + r * nn.col(i);
    }
  };
  pieces.push_back(std::move(p));
  // The sphere touches the plate at one point and hides almost nothing of it.
  print = round(foot, 0.0);
  return 2.0 * r;
}

/// The plate, its points outside the parts' footprints.
Piece plate(std::vector<Footprint> prints) {
  Piece p;
  p.truth = Primitive{Plane{Eigen::Vector3d::UnitZ(), 0.0}};
  p.area = 4.0 * kPlateHalfSide * kPlateHalfSide;
  for (const Footprint& f : prints)
    p.area -= f.area;
  p.sample = [prints](std::size_t n, Rng& rng, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& nn) {
    x.resize(3, static_cast<Eigen::Index>(n));
    nn.resize(3, static_cast<Eigen::Index>(n));
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      Eigen::Vector2d q;
      bool hidden = true;
      while (hidden) {
        q = Eigen::Vector2d(uniform(rng, -kPlateHalfSide, kPlateHalfSide),
                            uniform(rng, -kPlateHalfSide, kPlateHalfSide));
        hidden = std::any_of(prints.begin(), prints.end(),
                             [&](const Footprint& f) { return f.hides(q); });
      }
      x.col(i) = Eigen::Vector3d(q.x(), q.y(), 0.0);
      nn.col(i) = Eigen::Vector3d::UnitZ();
    }
  };
  return p;
}

}  // namespace

std::int32_t truthTypeCode(const SurfaceTruth& truth) {
  if (const auto* p = std::get_if<Primitive>(&truth))
    return static_cast<std::int32_t>(p->index());
  return 5 + static_cast<std::int32_t>(std::get<KinematicSurface>(truth).type);
}

void KinematicSceneParameters::validate() const {
  if (points < 100)
    throw InvalidParameterError("kinematic scene: points must be at least 100");
  if (!(noise >= 0.0 && noise <= 0.05))
    throw InvalidParameterError("kinematic scene: noise must be in [0, 0.05]");
}

KinematicScene sampleKinematicScene(const KinematicSceneParameters& parameters) {
  parameters.validate();
  Rng rng(parameters.seed);
  using Part = double (*)(const Eigen::Vector2d&, Rng&, std::vector<Piece>&, Footprint&);
  std::vector<Part> parts = {turnedPart, extrudedPart, threadedRod};
  if (parameters.primitives) {
    parts.push_back(cylinderPart);
    parts.push_back(spherePart);
  }
  // Five places on the plate, dealt to the parts at random, each moved a little.
  std::vector<Eigen::Vector2d> places = {
      {-0.65, -0.65}, {0.65, -0.65}, {-0.65, 0.65}, {0.65, 0.65}, {0.0, 0.0}};
  for (std::size_t k = places.size() - 1; k > 0; --k)
    std::swap(places[k], places[std::uniform_int_distribution<std::size_t>(0, k)(rng)]);
  std::vector<Piece> pieces;
  std::vector<Footprint> prints(parts.size());
  std::vector<double> sizes;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const Eigen::Vector2d at =
        places[k] + Eigen::Vector2d(uniform(rng, -0.08, 0.08), uniform(rng, -0.08, 0.08));
    sizes.push_back(parts[k](at, rng, pieces, prints[k]));
  }
  pieces.insert(pieces.begin(), plate(prints));

  KinematicScene scene;
  std::sort(sizes.begin(), sizes.end());
  scene.median_size = sizes.size() % 2
                          ? sizes[sizes.size() / 2]
                          : 0.5 * (sizes[sizes.size() / 2 - 1] + sizes[sizes.size() / 2]);
  double total = 0.0;
  for (const Piece& p : pieces)
    total += p.area;
  std::vector<std::size_t> counts;
  std::size_t given = 0;
  for (const Piece& p : pieces) {
    counts.push_back(static_cast<std::size_t>(std::floor(parameters.points * p.area / total)));
    given += counts.back();
  }
  counts[0] += parameters.points - given;  // the rest to the plate
  const auto n = static_cast<Eigen::Index>(parameters.points);
  scene.points.resize(3, n);
  scene.normals.resize(3, n);
  scene.labels.reserve(parameters.points);
  Eigen::Index at = 0;
  for (std::size_t l = 0; l < pieces.size(); ++l) {
    Eigen::Matrix3Xd x, nn;
    pieces[l].sample(counts[l], rng, x, nn);
    scene.points.middleCols(at, x.cols()) = x;
    scene.normals.middleCols(at, x.cols()) = nn;
    scene.labels.insert(scene.labels.end(), counts[l], static_cast<std::int32_t>(l));
    scene.truth.push_back(pieces[l].truth);
    at += x.cols();
  }
  if (parameters.noise > 0.0) {
    std::normal_distribution<double> gauss(0.0, parameters.noise * scene.median_size);
    for (Eigen::Index i = 0; i < n; ++i)
      scene.points.col(i) += randomVector<3>(gauss, rng);
  }
  return scene;
}

}  // namespace slipfit
