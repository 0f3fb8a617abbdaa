#pragma once
/// \file The declarations the samplers share (primitive, torus, motion surface): one text and one
/// range for the same option wherever it appears.

#include "slipfit/core/angle_units.h"
#include "slipfit/core/parameter_declaration.h"

namespace slipfit {

/// `points`: how many points lie on the surface (outliers come on top).
inline ParameterDeclaration surfaceSamplesParameter() {
  return parameter("points", "Surface samples (outliers come on top).")
      .in("points")
      .between(1, 1e9);
}

/// `noise`: σ of the isotropic Gaussian position noise, in the cloud's units.
inline ParameterDeclaration positionNoiseParameter() {
  return parameter("noise", "σ of Gaussian noise added to each coordinate.").in("units").atLeast(0);
}

/// `normal_noise`: σ of the normals' perturbation, declared in degrees (field in radians).
inline ParameterDeclaration normalNoiseParameter() {
  return parameter("normal_noise", "σ of the perturbation of the normals.")
      .in("deg", kDegree)
      .atLeast(0);
}

}  // namespace slipfit
