#pragma once
/// \file Scenes for simulated range sensors, built of bounded pieces of the five primitives
/// (surface_piece.h), each piece one true primitive. Metres.
///
/// - tabletop: the corner of a room (floor, two walls), a table (top, 3 cm edges, underside, four
///   legs) with 3–7 objects on it — cartons, cups (outer and inner wall 4 mm apart, inner
///   bottom), balls, cones and rings — and 2–4 larger ones on the floor (boxes, bins, balls,
///   traffic cones, tyres): what a depth camera sees at 0.6–3 m;
/// - yard: 60 × 60 m of ground with a house (walls, gable roof), tanks with cone, dome or flat
///   roofs, a silo with a dome, a spherical tank, posts, a sand pile and a tyre: what a
///   terrestrial or airborne LiDAR sees.
///
/// Objects stand on their support and do not overlap; sizes and places are drawn from the seed.

#include "slipfit/sampling/surface_piece.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

namespace slipfit {

enum class SensorSetting { tabletop, yard };
constexpr std::array<std::pair<SensorSetting, std::string_view>, 2> kSensorSettingNames{{
    {SensorSetting::tabletop, "tabletop"},
    {SensorSetting::yard, "yard"},
}};

struct SensorScene {
  std::vector<SurfacePiece> pieces;  ///< piece i is true primitive i (or that of its `continues`)
  Eigen::Vector3d focus;             ///< where a sensor looks: the table's top, the yard's centre
  double support_height = 0.0;       ///< the table top's height (tabletop), 0 (yard)
  double extent = 0.0;               ///< half the side of the ground square
};

/// The scene of \a setting for \a seed. Deterministic.
SensorScene sensorScene(SensorSetting setting, std::uint64_t seed);

}  // namespace slipfit
