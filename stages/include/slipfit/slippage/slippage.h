#pragma once
/// \file Slippage analysis (Gelfand & Guibas, "Shape segmentation using local slippage analysis",
/// SGP 2004): the rigid motions that slide a point set along itself, read off the near-null space
/// of the 6 × 6 matrix Σ wᵢ [pᵢ × nᵢ; nᵢ][pᵢ × nᵢ; nᵢ]ᵀ, and the primitive they reveal.
/// Derivation: docs/THEORY.md §5.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace slipfit {

/// What the slippable motions say about the surface.
enum class SlippageType : std::int32_t {
  none,        ///< no slippable motion: a general (rigid) surface
  plane,       ///< 3 motions: two translations and the rotation about the normal
  sphere,      ///< 3 motions: rotations about the centre
  cylinder,    ///< 2 motions: translation along and rotation about the axis
  cone,        ///< 1 rotation; straight profile meeting the axis
  torus,       ///< 1 rotation; circular profile
  revolution,  ///< 1 rotation; another profile
  extrusion,   ///< 1 translation
  helix,       ///< 1 screw motion
  degenerate   ///< too few points, collinear points, or more than 3 motions
};
constexpr std::array<std::pair<SlippageType, std::string_view>, 10> kSlippageTypeNames{{
    {SlippageType::none, "none"},
    {SlippageType::plane, "plane"},
    {SlippageType::sphere, "sphere"},
    {SlippageType::cylinder, "cylinder"},
    {SlippageType::cone, "cone"},
    {SlippageType::torus, "torus"},
    {SlippageType::revolution, "revolution"},
    {SlippageType::extrusion, "extrusion"},
    {SlippageType::helix, "helix"},
    {SlippageType::degenerate, "degenerate"},
}};
std::string_view slippageTypeName(SlippageType type);

/// The fittable primitive of a slippage type (plane, sphere, cylinder, cone), or none.
std::optional<PrimitiveType> primitiveTypeOf(SlippageType type);

struct SlippageOptions {
  /// Eigenvalues λ ≤ threshold · λ_max (of the normalised matrix) may be slippable. Candidate
  /// counts are ranked by the gap λ_{k+1} / λ_k; the count is the best-ranked one whose ideal
  /// motions slip (energy below √(λ_k λ_{k+1})), and when several primitives slip, the one with the
  /// lowest BIC on the point-to-surface distances.
  double threshold = 0.05;
  /// Profile fits (line, circle) of a surface of revolution must have an RMS residual below this
  /// fraction of the point set's RMS radius.
  double profile_tolerance = 0.05;
  /// |pitch| below this fraction of the RMS radius per radian counts as a pure rotation.
  double pitch_tolerance = 0.05;
  /// Relative eigenvalue (of the normalised matrix) that noise gives a slippable motion at the
  /// least; eigenvalues are raised to it before their ratios are taken, so that a motion that
  /// slips exactly (λ = 0: a translation with exact normals) next to one that position noise
  /// lifts (a rotation, λ ≈ (σ / RMS radius)²) is not an infinite gap. The default is rounding;
  /// classifyShape (shape_classification.h) sets the position noise it measures.
  double noise_floor = 1e-6;
  /// A three-motion set that fits both a plane and a sphere whose radius exceeds this many RMS
  /// radii of the point set is a plane (the sagitta is under 1 % of the patch).
  double flat_radius = 50.0;

  /// Each user-facing field with its one declaration (parameter_declaration.h); noise_floor is
  /// set by the library itself.
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.threshold,
          parameter("threshold",
                    "Eigenvalues below threshold × the largest may be slippable; candidate counts "
                    "are ranked by their spectral gap and the first whose ideal motions slip is "
                    "taken (see docs/THEORY.md §5).")
              .between(1e-9, 0.5));
    visit(
        self.profile_tolerance,
        parameter("profile_tolerance",
                  "RMS residual (fraction of the RMS radius) a line or circle profile may have to "
                  "call a surface of revolution a cone or torus.")
            .between(1e-6, 1));
    visit(self.pitch_tolerance,
          parameter("pitch_tolerance",
                    "Screw pitch per radian (fraction of the RMS radius) below which a motion is a "
                    "pure rotation.")
              .between(0, 10));
    visit(self.flat_radius,
          parameter("flat_radius",
                    "A point set fitting both a plane and a sphere whose radius exceeds this many "
                    "RMS radii of the set is a plane.")
              .between(1, 1e9));
  }

  /// Throws InvalidParameterError naming the field, its value and its declared range (noise_floor:
  /// ≥ 0 and finite).
  void validate() const;
};

struct SlippageResult {
  SlippageType type = SlippageType::degenerate;
  std::string reason;  ///< for degenerate results
  int motions = 0;     ///< number of slippable motions
  Eigen::Matrix<double, 6, 1> spectrum =
      Eigen::Matrix<double, 6, 1>::Zero();  ///< λ/λ_max ascending
  /// The slippable motions [ω; v] (world coordinates, one per column, ω unit or zero).
  Eigen::Matrix<double, 6, Eigen::Dynamic> basis;
  std::optional<Eigen::Vector3d> axis;    ///< rotation / extrusion / screw axis direction
  std::optional<Eigen::Vector3d> point;   ///< a point on the rotation or screw axis
  std::optional<Eigen::Vector3d> center;  ///< sphere centre
  std::optional<Eigen::Vector3d> normal;  ///< plane normal
  std::optional<double> pitch;            ///< helix: translation per radian, world units
  /// The primitive implied by the motions (initial guess for weighted fitting) when the type is
  /// plane, sphere, cylinder or cone.
  std::optional<Primitive> primitive;
  double scale = 1.0;  ///< the RMS radius used to normalise
  /// The margin of the count: λ_{k+1} / λ_k of the spectrum lifted by the noise floor (k = 0:
  /// how far the smallest eigenvalue is above the floor).
  double gap = 0.0;
  double threshold = 0.0;    ///< SlippageOptions::threshold the count was made with
  double noise_floor = 0.0;  ///< SlippageOptions::noise_floor the count was made with
};

/// The 6 × 6 slippage matrix of (already normalised) points and normals, weighted.
Eigen::Matrix<double, 6, 6> slippageMatrix(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                           const Eigen::Ref<const Eigen::VectorXd>& weights);

/// Centres the points on their weighted centroid and scales them to unit RMS radius (so that
/// rotations and translations are commensurate), builds and decomposes the matrix, counts and
/// classifies the slippable motions and recovers the primitive's parameters. Normals may have any
/// sign and length; zero-weight points are ignored.
SlippageResult analyzeSlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                               const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                               const Eigen::Ref<const Eigen::VectorXd>& weights,
                               const SlippageOptions& options = {});

/// Every reading of the spectrum whose ideal motions slip (one per candidate count, see
/// SlippageOptions::threshold), the one analyzeSlippage reports first. A single degenerate or
/// `none` result when nothing slips.
std::vector<SlippageResult> slippageReadings(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                             const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                             const Eigen::Ref<const Eigen::VectorXd>& weights,
                                             const SlippageOptions& options = {});

}  // namespace slipfit
