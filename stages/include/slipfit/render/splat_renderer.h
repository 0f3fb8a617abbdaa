#pragma once
/// \file A small software renderer that draws a coloured point cloud as shaded, depth-tested
/// round splats seen through a pinhole camera — a picture of a segmentation without a 3D viewer.

#include "slipfit/core/parameter_declaration.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <vector>

namespace slipfit {

struct RenderParameters {
  int width = 1024;  ///< pixels, [16, 8192]
  int height = 768;  ///< pixels, [16, 8192]
  /// Camera position. Unset: from the bounding box, looking at its centre from the direction
  /// `view_direction`, far enough that the whole box fits the field of view.
  std::optional<Eigen::Vector3d> eye;
  std::optional<Eigen::Vector3d> target;                             ///< unset: the box centre
  Eigen::Vector3d view_direction = Eigen::Vector3d(1.0, -1.3, 1.1);  ///< from target to eye
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double field_of_view = 0.7;  ///< vertical, radians, (0, π)
  /// Splat radius in pixels. Unset: from the projected point density.
  std::optional<double> splat_radius;
  std::uint8_t background[3] = {255, 255, 255};
  bool legend = true;  ///< the caller draws a legend on the image (drawLegend)
  /// Turn to the points and narrow the field of view to them (never wider than field_of_view).
  bool frame_points = true;

  /// The user-facing fields with their one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.view_direction,
          parameter("view_direction",
                    "Render: direction from the scene's centre towards the camera."));
    visit(self.eye, parameter("eye",
                              "Render: camera position (unset: the sensor's, looking along its z "
                              "axis, for an organized PCD or one with a VIEWPOINT; else along "
                              "view_direction, framing the cloud).")
                        .in("units"));
    visit(self.width, parameter("image_width", "Render: width.").in("pixels").between(16, 8192));
    visit(self.height, parameter("image_height", "Render: height.").in("pixels").between(16, 8192));
    visit(self.legend, parameter("legend",
                                 "Render: a legend in the top-left corner: each "
                                 "segment's colour, id, type and points, largest first."));
  }

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// Points \a parameters' camera from a range sensor at \a origin with \a orientation, in PCL's
/// sensor frame convention (the sensor looks along its +z, image rows run along its +y): the eye
/// at the origin, looking along the sensor's z axis at the median depth of the \a points in its
/// field of view (1 when none is), up the sensor's −y. Camera-frame scans are then seen as they
/// were taken, not framed by their far background. PCL also reads a pose as the map from the
/// points' frame to the world (its viewer moves points and camera alike): when fewer than half of
/// the points lie ahead of the posed sensor and more lie ahead of one at \a frame_origin (the
/// points' own origin) looking along their +z, that view is taken (a camera-frame scan saved with a
/// rotated VIEWPOINT, as PCL's office and tabletop scans are, would otherwise be seen from behind).
void useSensorCamera(RenderParameters& parameters, const Eigen::Vector3d& origin,
                     const Eigen::Quaterniond& orientation,
                     const Eigen::Ref<const Eigen::Matrix3Xf>& points,
                     const Eigen::Vector3d& frame_origin);

/// A line segment drawn over the splats, whatever lies in front of it (an axis inside a solid
/// shows): a black band 3 pixels wide with a 1-pixel core of its colour.
struct RenderLine {
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  std::uint8_t colour[3] = {0, 0, 0};
};

/// Renders 3 × N points with per-point RGB colours (3 × N) and optional normals (3 × N, any sign;
/// 0 columns: flat colour) into a row-major RGB image of width × height × 3 bytes. Lambert
/// shading with a head light; the nearest splat wins each pixel. Non-finite points are skipped.
/// Then \a lines are drawn on top, the part of each in front of the eye (the camera is the
/// splats': the lines do not move it).
std::vector<std::uint8_t> renderSplats(
    const Eigen::Ref<const Eigen::Matrix3Xf>& points,
    const Eigen::Ref<const Eigen::Matrix<std::uint8_t, 3, Eigen::Dynamic>>& colors,
    const Eigen::Ref<const Eigen::Matrix3Xf>& normals, const RenderParameters& parameters,
    const std::vector<RenderLine>& lines = {});

}  // namespace slipfit
