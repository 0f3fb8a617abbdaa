#include "slipfit/render/splat_renderer.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/core/median.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace slipfit {

void RenderParameters::validate() const {
  validateDeclared(*this, "render");
  if (!(field_of_view > 0.0 && field_of_view < kPi))
    throw InvalidParameterError("render: field_of_view must be in (0, 180) degrees");
  if (!(view_direction.allFinite() && view_direction.norm() > 0.0))
    throw InvalidParameterError("render: view_direction must be a non-zero vector");
  if (!(up.allFinite() && up.norm() > 0.0))
    throw InvalidParameterError("render: up must be a non-zero vector");
  if ((eye && !eye->allFinite()) || (target && !target->allFinite()))
    throw InvalidParameterError("render: eye and target must be finite");
  if (splat_radius && !(*splat_radius > 0.0 && *splat_radius <= 64.0))
    throw InvalidParameterError("render: splat_radius must be in (0, 64] pixels");
}

namespace {

/// A camera at \a eye with the axes of \a r (columns: image right, image down, ahead).
struct SensorView {
  Eigen::Vector3d eye;
  Eigen::Matrix3d r;
};

/// The depths along the view's axis of the \a points in front of it.
std::vector<double> depthsAhead(const SensorView& view,
                                const Eigen::Ref<const Eigen::Matrix3Xf>& points) {
  std::vector<double> depth;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const double z = (points.col(i).cast<double>() - view.eye).dot(view.r.col(2));
    if (std::isfinite(z) && z > 0.0)
      depth.push_back(z);
  }
  return depth;
}

}  // namespace

void useSensorCamera(RenderParameters& parameters, const Eigen::Vector3d& origin,
                     const Eigen::Quaterniond& orientation,
                     const Eigen::Ref<const Eigen::Matrix3Xf>& points,
                     const Eigen::Vector3d& frame_origin) {
  // The pose read as the sensor's place among the points, and the points read as the sensor's own
  // frame (PCL's viewer applies the pose to the points and the camera alike, so the sensor then
  // looks along the points' +z from their origin): the one that sees more of them.
  const SensorView posed{origin, orientation.normalized().toRotationMatrix()};
  const SensorView own{frame_origin, Eigen::Matrix3d::Identity()};
  std::vector<double> depth = depthsAhead(posed, points);
  const SensorView* view = &posed;
  if (2 * depth.size() < static_cast<std::size_t>(points.cols()) &&
      (!posed.r.isIdentity(1e-12) || origin != frame_origin)) {
    std::vector<double> other = depthsAhead(own, points);
    if (other.size() > depth.size()) {
      depth = std::move(other);
      view = &own;
    }
  }
  double median = 1.0;
  if (!depth.empty())
    median = medianInPlace(depth);
  parameters.eye = view->eye;
  parameters.target = view->eye + median * view->r.col(2);
  parameters.up = -view->r.col(1);
}

std::vector<std::uint8_t> renderSplats(
    const Eigen::Ref<const Eigen::Matrix3Xf>& points,
    const Eigen::Ref<const Eigen::Matrix<std::uint8_t, 3, Eigen::Dynamic>>& colors,
    const Eigen::Ref<const Eigen::Matrix3Xf>& normals, const RenderParameters& parameters,
    const std::vector<RenderLine>& lines) {
  parameters.validate();
  if (colors.cols() != points.cols() || (normals.cols() != 0 && normals.cols() != points.cols()))
    throw DegenerateInputError("render: points, colours and normals differ in number");
  const int w = parameters.width, h = parameters.height;
  std::vector<std::uint8_t> image(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  for (std::size_t i = 0; i < image.size(); ++i)
    image[i] = parameters.background[i % 3];

  Eigen::AlignedBox3d box;
  std::size_t finite = 0;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (points.col(i).allFinite()) {
      box.extend(points.col(i).cast<double>());
      ++finite;
    }
  if (finite == 0)
    return image;
  const Eigen::Vector3d target = parameters.target.value_or(box.center());
  const double tan_half = std::tan(parameters.field_of_view / 2);
  const double aspect = static_cast<double>(w) / h;
  const double radius = std::max(box.diagonal().norm() / 2, 1e-12);
  // The bounding sphere, shrunk by a fifth (scenes are flatter than their sphere), fits the
  // narrower field of view.
  const double distance = 0.8 * radius / std::sin(std::atan(tan_half * std::min(1.0, aspect)));
  const Eigen::Vector3d eye =
      parameters.eye.value_or(target + distance * parameters.view_direction.normalized());
  Eigen::Vector3d forward = (target - eye).normalized();
  const auto axes = [&](Eigen::Vector3d& right, Eigen::Vector3d& up) {
    right = forward.cross(parameters.up);
    if (right.norm() < 1e-9)
      right = forward.unitOrthogonal();
    right.normalize();
    up = right.cross(forward);
  };
  Eigen::Vector3d right, up;
  axes(right, up);
  double focal = h / (2 * tan_half);  // pixels
  if (parameters.frame_points) {
    // The points frame the picture: the view turns to the middle of their directions and the
    // field of view narrows to them (from the 1st to the 99th percentile of the directions
    // across and up, 4 % to spare), never widening past the configured one.
    std::vector<double> across, upward;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      const Eigen::Vector3d d = points.col(i).cast<double>() - eye;
      const double z = d.dot(forward);
      if (d.allFinite() && z > 0.0) {
        across.push_back(d.dot(right) / z);
        upward.push_back(d.dot(up) / z);
      }
    }
    if (across.size() >= 2) {
      const double u0 = quantile(across, 0.01), u1 = quantile(across, 0.99);
      const double v0 = quantile(upward, 0.01), v1 = quantile(upward, 0.99);
      const double needed =
          1.04 * std::max(0.5 * (v1 - v0), 0.5 * (u1 - u0) / (static_cast<double>(w) / h));
      if (needed > 1e-9 && needed < tan_half) {
        forward = (forward + 0.5 * (u0 + u1) * right + 0.5 * (v0 + v1) * up).normalized();
        axes(right, up);
        focal = h / (2 * needed);
      }
    }
  }

  // Splat radius: the spacing of the points as they would cover the box's projected area.
  const double depth = (box.center() - eye).norm();
  const double projected_area = kPi * std::pow(focal * radius / depth, 2);
  const double r = parameters.splat_radius.value_or(
      std::clamp(1.1 * std::sqrt(projected_area / static_cast<double>(finite)), 1.0, 8.0));
  const int ri = static_cast<int>(std::ceil(r));

  std::vector<float> zbuf(static_cast<std::size_t>(w) * static_cast<std::size_t>(h),
                          std::numeric_limits<float>::infinity());
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (!points.col(i).allFinite())
      continue;
    const Eigen::Vector3d d = points.col(i).cast<double>() - eye;
    const double z = d.dot(forward);
    if (z <= 1e-9 * depth)
      continue;
    const double u = w / 2.0 + focal * d.dot(right) / z;
    const double v = h / 2.0 - focal * d.dot(up) / z;
    double shade = 1.0;
    if (normals.cols() != 0 && normals.col(i).allFinite() && normals.col(i).norm() > 0)
      shade =
          0.35 + 0.65 * std::abs(normals.col(i).cast<double>().normalized().dot(d.normalized()));
    std::uint8_t rgb[3];
    for (int c = 0; c < 3; ++c)
      rgb[c] = static_cast<std::uint8_t>(std::lround(colors(c, i) * shade));
    const int cu = static_cast<int>(std::floor(u)), cv = static_cast<int>(std::floor(v));
    for (int y = cv - ri; y <= cv + ri; ++y) {
      if (y < 0 || y >= h)
        continue;
      for (int x = cu - ri; x <= cu + ri; ++x) {
        if (x < 0 || x >= w)
          continue;
        const double dx = x + 0.5 - u, dy = y + 0.5 - v;
        if (dx * dx + dy * dy > r * r)
          continue;
        const std::size_t px =
            static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
        if (z >= zbuf[px])
          continue;
        zbuf[px] = static_cast<float>(z);
        std::copy(rgb, rgb + 3, image.begin() + static_cast<std::ptrdiff_t>(3 * px));
      }
    }
  }

  // The lines, clipped to the half-space in front of the eye, stepped a pixel at a time.
  const double near = 1e-6 * depth;
  const auto paint = [&](double u, double v, int half, const std::uint8_t* rgb) {
    const int cu = static_cast<int>(std::floor(u)), cv = static_cast<int>(std::floor(v));
    for (int y = cv - half; y <= cv + half; ++y)
      for (int x = cu - half; x <= cu + half; ++x)
        if (x >= 0 && x < w && y >= 0 && y < h)
          std::copy(rgb, rgb + 3, image.begin() + 3 * (static_cast<std::ptrdiff_t>(y) * w + x));
  };
  for (const int pass : {0, 1})  // the black bands of every line first, then their cores
    for (const RenderLine& line : lines) {
      Eigen::Vector3d a = line.from - eye, b = line.to - eye;
      if (!a.allFinite() || !b.allFinite())
        continue;
      double za = a.dot(forward), zb = b.dot(forward);
      if (za < near && zb < near)
        continue;
      if (za < near)
        a += (near - za) / (zb - za) * (b - a);
      else if (zb < near)
        b += (near - zb) / (za - zb) * (a - b);
      za = a.dot(forward);
      zb = b.dot(forward);
      const Eigen::Vector2d pa(w / 2.0 + focal * a.dot(right) / za,
                               h / 2.0 - focal * a.dot(up) / za);
      const Eigen::Vector2d pb(w / 2.0 + focal * b.dot(right) / zb,
                               h / 2.0 - focal * b.dot(up) / zb);
      // The part within the image (and 2 pixels round it): Liang–Barsky on the parameter t of
      // pa + t (pb − pa).
      const Eigen::Vector2d d = pb - pa;
      double t0 = 0.0, t1 = 1.0;
      const double lo[2] = {-2.0, -2.0}, hi[2] = {w + 2.0, h + 2.0};
      for (int a = 0; a < 2 && t0 <= t1; ++a) {
        if (d[a] == 0.0) {
          if (pa[a] < lo[a] || pa[a] > hi[a])
            t1 = -1.0;
          continue;
        }
        const double e0 = (lo[a] - pa[a]) / d[a], e1 = (hi[a] - pa[a]) / d[a];
        t0 = std::max(t0, std::min(e0, e1));
        t1 = std::min(t1, std::max(e0, e1));
      }
      if (!(t0 <= t1))
        continue;
      const Eigen::Vector2d from = pa + t0 * d, to = pa + t1 * d;
      const auto steps = static_cast<int>(std::ceil((to - from).norm()));
      static const std::uint8_t black[3] = {0, 0, 0};
      for (int k = 0; k <= steps; ++k) {
        const Eigen::Vector2d q =
            steps == 0 ? from : from + (to - from) * (static_cast<double>(k) / steps);
        if (pass == 0)
          paint(q.x(), q.y(), 1, black);
        else
          paint(q.x(), q.y(), 0, line.colour);
      }
    }
  return image;
}

}  // namespace slipfit
