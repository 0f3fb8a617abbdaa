#pragma once
/// \file The segmentation's tuning constants, in one place, each with the derivation or the
/// measurement that set it. The phases that use a constant are named by their number (Phase,
/// segmentation_phase.h; docs/THEORY.md §6 uses the same numbers). Not user options: a value here
/// follows from the statistics of the noise or was measured on the development data; changing one
/// changes every output, and the suite's figures must be measured again.

#include <cstddef>

namespace slipfit {

struct SegmentationTuning {
  // ---- 1 estimate_scale: the tolerances -------------------------------------------------------
  /// The default tolerance is noise_factor σ̂ + spacing_factor × the median spacing: 3 σ keeps
  /// 99.7 % of a Gaussian's points.
  static constexpr double noise_factor = 3.0;
  /// The floor for noise-free data (CAD: σ̂ ≈ 0), a twentieth of the spacing: it admits float
  /// rounding and the sagitta of fits made on part of a region while it grows. Distances closer
  /// than this cannot tell two primitives apart (the edge margin of phases 7–9 and 11).
  static constexpr double spacing_factor = 0.05;
  /// Steps of a quantized depth axis added to a point's tolerance: a point lies up to half a step
  /// off its surface along that axis, and a disparity sensor's noise is about half a step too.
  static constexpr double step_factor = 2.0;
  /// The noise is the lower quartile over the neighborhoods' residuals (robust to the half of them
  /// that straddle edges; the median was not), each scaled by the same quantile of χ²_ν / ν.
  static constexpr double noise_quantile = 0.25;
  static constexpr double noise_quantile_z = -0.6744897501960817;  ///< z-score of the quartile
  /// The noise is estimated on at most this many neighborhoods (evenly strided): a sample is enough
  /// for a quartile.
  static constexpr std::size_t noise_sample = 20000;
  /// ... of a whole cloud. A part of one (a tile of a tiled run: SegmentationParameters::
  /// noise_sample_share) samples its share of them, but at least this many: the lower quartile
  /// of 2,000 χ²_6 / 6 estimates has a standard error of 2 % (1 % in σ̂; 0.3 % at 20,000).
  static constexpr std::size_t least_noise_sample = 2000;
  /// Depth levels whose median step is below this many times σ̂ are not modelled (depth stored in
  /// millimetres under centimetres of noise): their rounding adds less than (0.5 / √12)² = 2 % to
  /// the noise's variance. A disparity sensor's steps are about 2 σ (the simulated Kinect's).
  static constexpr double fine_levels = 1.5;
  /// Each point's own σ is the lower quartile over this many sampled neighborhoods around it
  /// (phase 1's localNoise): the quartile of 16 χ²_6 estimates is within about 12 % of σ (its
  /// standard error), and 16 samples of 20,000 span a surface of 0.08 % of the cloud.
  static constexpr std::size_t local_noise_samples = 16;
  /// ... and over at least this many points' worth of samples: on a small cloud, sampled at every
  /// point, 16 samples are one ring, inside the band of a crease; 256 points are a patch of
  /// which fewer than three quarters straddle it.
  static constexpr std::size_t local_noise_points = 256;
  /// The quantile of the pooled estimates that is a point's own σ², each estimate scaled by the
  /// same quantile of χ²_ν / ν. Lower than the median: a pool that straddles a crease reads
  /// high. Measured on simulated terrestrial LiDAR (development seeds 1–6, mean IoU) and Fit4CAD
  /// (Dice / mIoU / type): 0.25 gave 0.787 and 0.9333 / 0.9020 / 0.9747; 0.4 0.807 and 0.9333 /
  /// 0.9021 / 0.9747; the median 0.819 and 0.9328 / 0.9008 / 0.9717, below the Fit4CAD gate.
  static constexpr double local_noise_quantile = 0.4;
  static constexpr double local_noise_quantile_z = -0.2533471031357997;  ///< its z-score
  /// A point keeps the cloud's σ̂ unless its own is larger by this factor: the simpler model
  /// unless the data demand the other. Measured: 1.5 raised the sparse shapes of the 1M random
  /// scene (mean IoU 0.9725 against 0.974 before) and 2.0 left terrestrial LiDAR walls too tight
  /// (development seeds 1, 2: mean IoU 0.85 / 0.53 against 0.85 / 0.63 at 1.75).
  static constexpr double local_noise_ratio = 1.75;
  /// A neighborhood whose median distance along its second principal axis is below this share of
  /// that along its first is drawn out along a line (5 : 1): its height-field residual does not
  /// measure the noise (localNoise).
  static constexpr double least_aspect = 0.2;
  /// A neighborhood holds two sheets of a thin wall when their means lie apart by more than this
  /// many times the points' RMS off them (one noisy surface split in two leaves its halves 2.7 RMS
  /// apart; 6 split noisy neighborhoods and failed three suite tests) and a tenth of its radius.
  static constexpr double sheet_separation = 20.0;
  static constexpr double sheet_radius_share = 0.1;

  // ---- 2–3 seeding ----------------------------------------------------------------------------
  /// The default smallest segment: an absolute count (a fraction of N starves the small shapes of
  /// a large scene); small faces of CAD parts have 20–60 points.
  static constexpr std::size_t default_min_points = 20;
  /// A grown region's type changes only when another type's median distance is below this share
  /// of its own (a BIC margin, or the RMS, let a wide sphere absorb the crease points of a plane).
  static constexpr double retype_share = 0.75;
  /// A gap this many tolerances wide between the offsets of a seed's 2-ring along its normal
  /// divides two sheets of a thin wall. The tolerance is 3 σ̂ (plus a twentieth of the spacing): a
  /// gap of 12 σ̂ between neighbouring offsets of one noisy surface does not occur.
  static constexpr double sheet_gap = 4.0;

  // ---- 4, 10, 11 merging ----------------------------------------------------------------------
  /// A region this many times the size of another dominates their union's fit (4) and may absorb
  /// it (10).
  static constexpr std::size_t dominates = 4;
  /// Phase 10 passes, each on the regions the one before left (a speck that touched only another
  /// speck can join the region that absorbed it).
  static constexpr int absorb_passes = 4;
  /// A union's primitive must explain each region's points with an RMS distance within this many
  /// times their noise (their own σᵢ, as their own primitive does when that is worse): a ball or
  /// a ring on a far table lies within the table's tolerance (ε plus two depth steps, 4 cm at
  /// 2.4 m), and the table's RMS, swollen by its far rows' noise, hardly moves when it takes them.
  /// Twice: a depth camera's rounding to levels is correlated along the surface, so a region's
  /// RMS off its own primitive reads up to about 1.5 σ̂ (simulated Kinect frames, 2–3 m).
  static constexpr double union_noise_ratio = 2.0;
  /// The larger region's own ratio to its noise is read from this many of its members.
  static constexpr std::size_t ratio_sample = 2048;

  // ---- 5–6 types and fillets ------------------------------------------------------------------
  /// A wide region's type is revisited when a candidate's median normal angle is less than its
  /// own primitive's over this ratio (its normals turn beyond their noise).
  static constexpr double normal_turn_ratio = 2.0;
  /// The parameters a fillet adds (a cylinder's five) in the BIC against the sharp crease.
  static constexpr double fillet_parameters = 5.0;
  /// The most points a fillet's radius is chosen on (evenly strided).
  static constexpr std::size_t fillet_sample = 4000;

  // ---- 7 refine_boundaries --------------------------------------------------------------------
  /// A boundary moves a ring of points per pass; eight passes cross the band a plane takes off a
  /// tangent fillet at the 1 M-point scenes' density.
  static constexpr int boundary_passes = 8;
  /// How much lower (in squared standard units) another primitive's cost must be for a point
  /// within the noise of both to move: 4, a likelihood ratio of e² ≈ 7.
  static constexpr double stay_cost = 4.0;
  /// After two passes, a pass runs while it moves fewer than this share of the points the one
  /// before moved (on PCL's Kinect scans the rim segments crept into the table a ring per pass).
  static constexpr double settling = 0.5;
  /// Two distances within this share of the point's tolerance (2σ̂ of its 3σ̂, and as much of its
  /// depth steps) are a tie the neighborhood decides.
  static constexpr double tie_share = 2.0 / 3.0;

  // ---- 3, 9 small faces and scattered points --------------------------------------------------
  /// The fewest free points tried as a face (a plane needs 3, and 3 per parameter must hold).
  static constexpr std::size_t smallest_patch = 8;
  /// The share of a small face's own points its fit must hold.
  static constexpr double held = 0.8;
  /// Points lying further apart than this many times the points of the regions around them are
  /// scattered through the volume, not a surface. Points sampled at random on a surface with
  /// density ρ are a median 0.47/√ρ from their nearest; twice that is a surface sampled a quarter
  /// as densely as its surroundings.
  static constexpr double scattered = 2.0;
  /// A set sparser than `scattered` × the cloud's median spacing with no region around to compare
  /// its sampling with (a post 14–20 m from a LiDAR, its returns 5–7 cm apart where the cloud's
  /// median spacing is 1 cm) is scattered unless it lies in a sheet: √(λ₀/λ₁) of its points below
  /// this. The 12-point neighbourhoods of three
  /// such posts (LiDAR scan seed 3) read a median of 0.20–0.22 (90th percentile 0.31–0.34); twelve
  /// points uniform in a cube or a ball read below 0.25 three times in 10,000, and must then still
  /// fit a primitive and hold 3 points per parameter of their 2-ring (ScatteredPoints tests: no
  /// outlier region).
  static constexpr double isolated_thinness = 0.25;

  // ---- 12 drop_non_surfaces -------------------------------------------------------------------
  /// Between a surface's RMS distance (≈ 0.33 ε with Gaussian noise, ε = 3σ) and that of a slab
  /// filled at random (ε/√3 ≈ 0.58 ε).
  static constexpr double volume_ratio = 0.45;
  /// ... unless the points' own neighborhoods are thin: a surface whose deviations exceed its
  /// tolerance (noise correlated over more than a neighborhood — a stereo camera's, a bumpy
  /// floor) fills its slab too, but each point's neighborhood lies in a sheet, while points
  /// scattered through a volume have neighborhoods as deep as they are wide. Thin: the median over
  /// the region of √(λ₀/λ₁) of the neighborhoods below this (noise σ across a neighborhood of
  /// radius about 2 spacings reads σ/s at most; a uniform ball reads 1).
  static constexpr double volume_thinness = 0.5;
  static constexpr std::size_t volume_thinness_sample = 64;  ///< members looked at, evenly spaced

  // ---- 13 join_occluded_pieces ----------------------------------------------------------------
  /// Of each region's members, this many evenly spaced are checked against another region's
  /// primitive before their union is fitted.
  static constexpr std::size_t piece_sample = 64;
};

}  // namespace slipfit
