#pragma once
/// \file primitives.yaml: one entry per fitted primitive. Field names are fixed by the fitting
/// issue (id, type, the parameters by name, inliers, rms_distance, max_distance, status); later
/// stages add fields, never rename these.

#include "slipfit/fitting/kinematic_fit.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/slippage/slippage.h"

#include <yaml-cpp/node/node.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace slipfit::pipeline {

struct PrimitiveRecord {
  int id = 0;
  std::optional<int> label;  ///< the point label the primitive was fitted to
  FitResult fit;
  bool fitted = true;                      ///< false: no weighted fit (type from slippage only)
  std::optional<SlippageResult> slippage;  ///< the slippage verdict, when one was made
  /// The kinematic surface of a kinematic verdict (revolution, extrusion, helix): written under
  /// `kinematic` with its profile in place of the spectrum's motion alone.
  std::optional<KinematicFit> kinematic;
  std::size_t inliers = 0;  ///< points with positive weight within the inlier distance
  double inlier_distance = 0.0;
  std::map<std::string, std::string> extra;  ///< further scalar fields (added by later stages)
};

/// The YAML text of the report (parameters of the refined fit; the closed form under `algebraic`).
/// Positions are written in the input's frame: the fits' + \a shift (PointData::frame), which is
/// listed as `global_shift` when it is not zero.
std::string primitivesYaml(const std::vector<PrimitiveRecord>& records, const std::string& source,
                           const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

/// The primitive of one entry of primitives.yaml (its `type` and parameters, as primitivesYaml
/// writes them), less \a shift: the fit in the frame the parameters were written from. Empty for an
/// entry whose status is not ok, of another type (a kinematic surface) or missing a parameter.
std::optional<Primitive> readPrimitive(const YAML::Node& entry,
                                       const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

}  // namespace slipfit::pipeline
