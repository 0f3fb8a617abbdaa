#pragma once
// The kinematic class of each of the sampler's one-motion surfaces (motion_surface_sampler.h).
#include "slipfit/fitting/kinematic_surface.h"
#include "slipfit/sampling/motion_surface_sampler.h"

namespace slipfit::testing {

inline KinematicType kinematicTypeOf(MotionSurface surface) {
  switch (surface) {
    case MotionSurface::revolution:
      return KinematicType::revolution;
    case MotionSurface::extrusion:
    case MotionSurface::open_extrusion:
      return KinematicType::extrusion;
    case MotionSurface::helix:
    case MotionSurface::twisted_column:
      return KinematicType::helix;
  }
  return KinematicType::revolution;
}

}  // namespace slipfit::testing
