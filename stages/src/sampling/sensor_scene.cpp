#include "slipfit/sampling/sensor_scene.h"

#include "slipfit/core/angle_units.h"

#include <Eigen/Geometry>

#include <cmath>
#include <optional>
#include <random>

namespace slipfit {

namespace {

using Eigen::Vector3d;

/// Draws from the scene's generator.
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  double operator()(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  int count(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

 private:
  std::mt19937_64 rng_;
};

/// Footprints of the objects placed on one support: discs that must not overlap.
class Placer {
 public:
  void reserve(double x, double y, double radius) { taken_.push_back({x, y, radius}); }
  /// A centre in [x0, x1] × [y0, y1] for a footprint of \a radius clear of the others by
  /// \a gap; nothing after 200 tries.
  std::optional<Eigen::Vector2d> place(Draw& draw, double x0, double x1, double y0, double y1,
                                       double radius, double gap) {
    if (x1 - x0 < 2 * radius || y1 - y0 < 2 * radius)
      return std::nullopt;
    for (int attempt = 0; attempt < 200; ++attempt) {
      const Eigen::Vector2d c(draw(x0 + radius, x1 - radius), draw(y0 + radius, y1 - radius));
      bool clear = true;
      for (const auto& t : taken_)
        clear = clear && (c - Eigen::Vector2d(t[0], t[1])).norm() >= radius + t[2] + gap;
      if (clear) {
        reserve(c.x(), c.y(), radius);
        return c;
      }
    }
    return std::nullopt;
  }

 private:
  std::vector<std::array<double, 3>> taken_;
};

/// A box of w × d × h standing at \a base (the centre of its bottom), turned by \a yaw about z:
/// its top, four sides and, with \a bottom, its underside, normals outward.
void addBox(std::vector<SurfacePiece>& out, const Vector3d& base, double yaw, double w, double d,
            double h, bool top, bool bottom) {
  const Vector3d ex(std::cos(yaw), std::sin(yaw), 0.0), ey(-std::sin(yaw), std::cos(yaw), 0.0),
      ez = Vector3d::UnitZ();
  const Vector3d c0 = base - 0.5 * w * ex - 0.5 * d * ey;
  if (top)
    out.push_back(parallelogram(c0 + h * ez, w * ex, d * ey));
  if (bottom)
    out.push_back(parallelogram(c0, d * ey, w * ex));
  out.push_back(parallelogram(c0, w * ex, h * ez));
  out.push_back(parallelogram(c0 + d * ey, h * ez, w * ex));
  out.push_back(parallelogram(c0, h * ez, d * ey));
  out.push_back(parallelogram(c0 + w * ex, d * ey, h * ez));
}

/// Table-top objects, standing at \a base on a horizontal support.
void addCarton(std::vector<SurfacePiece>& out, Draw& draw, const Vector3d& base, double size) {
  addBox(out, base, draw(0.0, kPi), size * draw(0.5, 1.0), size * draw(0.5, 1.0), draw(0.08, 0.3),
         true, false);
}

void addCup(std::vector<SurfacePiece>& out, const Vector3d& base, double radius, double height) {
  const double wall = 0.004, floor = 0.006;
  const Vector3d ez = Vector3d::UnitZ();
  out.push_back(cylinderSide(base, ez, radius, height));
  SurfacePiece inner = cylinderSide(base, ez, radius - wall, height);
  inner.lo = floor;
  out.push_back(inner);
  out.push_back(disk(base + floor * ez, ez, 0.0, radius - wall));
}

/// A cone standing on its base of \a radius, apex up, its top \a cut of the height taken off.
void addCone(std::vector<SurfacePiece>& out, const Vector3d& base, double radius, double height,
             double cut) {
  out.push_back(coneBand(base + height * Vector3d::UnitZ(), -Vector3d::UnitZ(),
                         std::atan(radius / height), cut * height, height));
}

void addTabletop(SensorScene& scene, Draw& draw) {
  auto& out = scene.pieces;
  const Vector3d ez = Vector3d::UnitZ();
  // The room: floor up to two walls that meet in a corner behind and beside the table.
  const double wy = draw(1.4, 2.2), wx = draw(1.6, 2.4), wall = 2.5;
  out.push_back(parallelogram(Vector3d(-3, -3, 0), Vector3d(wx + 3, 0, 0), Vector3d(0, wy + 3, 0)));
  out.push_back(parallelogram(Vector3d(-3, wy, 0), Vector3d(wx + 3, 0, 0), wall * ez));
  out.push_back(parallelogram(Vector3d(wx, -3, 0), wall * ez, Vector3d(0, wy + 3, 0)));
  // The table: a 3 cm top (upper face, edges, underside) on four legs.
  const double height = draw(0.70, 0.78), w = draw(1.0, 1.6), d = draw(0.6, 0.9);
  const double yaw = draw(-0.25, 0.25), thick = 0.03;
  const Vector3d centre(draw(-0.3, 0.3), draw(-0.2, 0.3), 0.0);
  addBox(out, centre + (height - thick) * ez, yaw, w, d, thick, true, true);
  const Vector3d ex(std::cos(yaw), std::sin(yaw), 0.0), ey(-std::sin(yaw), std::cos(yaw), 0.0);
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      out.push_back(cylinderSide(centre + sx * (0.5 * w - 0.06) * ex + sy * (0.5 * d - 0.06) * ey,
                                 ez, 0.025, height - thick));
  scene.focus = centre + height * ez;
  scene.support_height = height;
  scene.extent = 3.0;
  // Objects on the table, placed in its own frame.
  Placer on_table;
  const int n_table = draw.count(3, 7);
  for (int i = 0; i < n_table; ++i) {
    const int kind = draw.count(0, 4);
    // carton side, cup radius, ball radius, cone base radius, ring major radius
    constexpr double kTableSizes[5][2] = {
        {0.06, 0.25}, {0.03, 0.05}, {0.03, 0.1}, {0.05, 0.12}, {0.04, 0.09}};
    const double size = draw(kTableSizes[kind][0], kTableSizes[kind][1]);
    const double footprint = kind == 0 ? 0.71 * size : size;
    const auto c = on_table.place(draw, -0.5 * w + 0.02, 0.5 * w - 0.02, -0.5 * d + 0.02,
                                  0.5 * d - 0.02, footprint, 0.03);
    if (!c)
      continue;
    const Vector3d base = centre + c->x() * ex + c->y() * ey + height * ez;
    switch (kind) {
      case 0:
        addCarton(out, draw, base, size);
        break;
      case 1:
        addCup(out, base, size, draw(0.08, 0.13));
        break;
      case 2:
        out.push_back(sphereCap(base + size * ez, size, ez));
        break;
      case 3:
        addCone(out, base, size, size * draw(1.5, 3.0), 0.15);
        break;
      default: {
        const double tube = size * draw(0.25, 0.35);
        out.push_back(torus(base + tube * ez, ez, size, tube));
      }
    }
  }
  // Larger objects on the floor beside and behind the table (the sensors stand in front).
  Placer on_floor;
  on_floor.reserve(centre.x(), centre.y(), 0.5 * std::hypot(w, d));
  const int n_floor = draw.count(2, 4);
  for (int i = 0; i < n_floor; ++i) {
    const int kind = draw.count(0, 4);
    // box side, bin radius, ball radius, traffic cone base radius, tyre major radius
    constexpr double kFloorSizes[5][2] = {
        {0.3, 0.6}, {0.12, 0.25}, {0.1, 0.25}, {0.12, 0.18}, {0.2, 0.3}};
    const double size = draw(kFloorSizes[kind][0], kFloorSizes[kind][1]);
    const double footprint = kind == 0 ? 0.71 * size : size + 0.1 * (kind == 4);
    const auto c = on_floor.place(draw, -2.5, wx - 0.05, centre.y(), wy - 0.05, footprint, 0.1);
    if (!c)
      continue;
    const Vector3d base(c->x(), c->y(), 0.0);
    switch (kind) {
      case 0:
        addBox(out, base, draw(0.0, kPi), size, size * draw(0.6, 1.0), draw(0.3, 0.8), true, false);
        break;
      case 1: {
        const double h = draw(0.4, 0.8);
        out.push_back(cylinderSide(base, ez, size, h));
        out.push_back(disk(base + h * ez, ez, 0.0, size));
        break;
      }
      case 2:
        out.push_back(sphereCap(base + size * ez, size, ez));
        break;
      case 3:
        addCone(out, base, size, draw(0.5, 0.75), 0.1);
        break;
      default: {
        const double tube = size * draw(0.3, 0.4);
        out.push_back(torus(base + tube * ez, ez, size, tube));
      }
    }
  }
}

/// A house of w × d with walls of \a eave and a gable roof rising \a rise along its length.
void addHouse(std::vector<SurfacePiece>& out, const Vector3d& base, double yaw, double w, double d,
              double eave, double rise) {
  const int walls = static_cast<int>(out.size());  // addBox's sides: −y, +y, −x, +x
  addBox(out, base, yaw, w, d, eave, false, false);
  const Vector3d ex(std::cos(yaw), std::sin(yaw), 0.0), ey(-std::sin(yaw), std::cos(yaw), 0.0),
      ez = Vector3d::UnitZ();
  const Vector3d a = base - 0.5 * w * ex - 0.5 * d * ey + eave * ez;
  const Vector3d up_y = 0.5 * d * ey + rise * ez;
  out.push_back(triangle(a, up_y, d * ey));  // gable at −x, on the −x wall's plane
  out.back().continues = walls + 2;
  out.push_back(triangle(a + w * ex, d * ey, up_y));  // gable at +x
  out.back().continues = walls + 3;
  out.push_back(parallelogram(a, w * ex, up_y));                                // roof, −y side
  out.push_back(parallelogram(a + d * ey, -0.5 * d * ey + rise * ez, w * ex));  // roof, +y side
}

void addYard(SensorScene& scene, Draw& draw) {
  auto& out = scene.pieces;
  const Vector3d ez = Vector3d::UnitZ();
  out.push_back(parallelogram(Vector3d(-30, -30, 0), Vector3d(60, 0, 0), Vector3d(0, 60, 0)));
  scene.focus = Vector3d::Zero();
  scene.extent = 30.0;
  Placer yard;
  yard.reserve(0.0, 0.0, 3.0);  // the terrestrial scanner's place
  const double lo = -25.0, hi = 25.0;
  {
    const double w = draw(8, 12), d = draw(6, 9);
    if (const auto c = yard.place(draw, lo, hi, lo, hi, 0.5 * std::hypot(w, d), 2.0))
      addHouse(out, Vector3d(c->x(), c->y(), 0), draw(0, kPi), w, d, draw(3, 4.5), draw(1.5, 3));
  }
  for (int i = 0, n = draw.count(1, 3); i < n; ++i) {
    const double r = draw(1.5, 3.5), h = draw(3, 8);
    const auto c = yard.place(draw, lo, hi, lo, hi, r, 2.0);
    if (!c)
      continue;
    const Vector3d base(c->x(), c->y(), 0);
    out.push_back(cylinderSide(base, ez, r, h));
    const int roof = draw.count(0, 2);
    if (roof == 0) {
      const double theta = draw(65, 80) * kDegree, rise = r / std::tan(theta);
      out.push_back(coneBand(base + (h + rise) * ez, -ez, theta, 0.0, rise));
    } else if (roof == 1) {
      const double alpha = draw(30, 60) * kDegree, rho = r / std::sin(alpha);
      out.push_back(sphereCap(base + (h - rho * std::cos(alpha)) * ez, rho, ez, std::cos(alpha)));
    } else {
      out.push_back(disk(base + h * ez, ez, 0.0, r));
    }
  }
  if (draw.count(0, 1) == 1) {  // a silo with a hemispherical dome
    const double r = draw(1.5, 2.5), h = draw(8, 12);
    if (const auto c = yard.place(draw, lo, hi, lo, hi, r, 2.0)) {
      out.push_back(cylinderSide(Vector3d(c->x(), c->y(), 0), ez, r, h));
      out.push_back(sphereCap(Vector3d(c->x(), c->y(), h), r, ez, 0.0));
    }
  }
  if (draw.count(0, 1) == 1) {  // a spherical tank resting on the ground
    const double r = draw(1.0, 2.5);
    if (const auto c = yard.place(draw, lo, hi, lo, hi, r, 2.0))
      out.push_back(sphereCap(Vector3d(c->x(), c->y(), r), r, ez));
  }
  for (int i = 0, n = draw.count(3, 6); i < n; ++i) {
    const double r = draw(0.08, 0.15);
    if (const auto c = yard.place(draw, lo, hi, lo, hi, r, 1.0))
      out.push_back(cylinderSide(Vector3d(c->x(), c->y(), 0), ez, r, draw(2, 4)));
  }
  if (draw.count(0, 1) == 1) {  // a sand pile
    const double theta = draw(50, 60) * kDegree, h = draw(1.0, 2.5);
    if (const auto c = yard.place(draw, lo, hi, lo, hi, h * std::tan(theta), 1.0))
      out.push_back(coneBand(Vector3d(c->x(), c->y(), h), -ez, theta, 0.0, h));
  }
  for (int i = 0, n = draw.count(0, 2); i < n; ++i) {  // tyres lying flat
    const double major = draw(0.45, 0.7), minor = draw(0.15, 0.25);
    if (const auto c = yard.place(draw, lo, hi, lo, hi, major + minor, 1.0))
      out.push_back(torus(Vector3d(c->x(), c->y(), minor), ez, major, minor));
  }
}

}  // namespace

SensorScene sensorScene(SensorSetting setting, std::uint64_t seed) {
  Draw draw(seed);
  SensorScene scene;
  if (setting == SensorSetting::tabletop)
    addTabletop(scene, draw);
  else
    addYard(scene, draw);
  return scene;
}

}  // namespace slipfit
