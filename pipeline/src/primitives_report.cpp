#include "slipfit/pipeline/primitives_report.h"

#include <yaml-cpp/yaml.h>

namespace slipfit::pipeline {

namespace {

void vec(YAML::Emitter& e, const char* key, const Eigen::Vector3d& v) {
  e << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << v.x() << v.y() << v.z()
    << YAML::EndSeq;
}

void parameters(YAML::Emitter& e, const Primitive& p, const Eigen::Vector3d& shift) {
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Plane>) {
          vec(e, "normal", s.normal);
          e << YAML::Key << "d" << YAML::Value << s.d + s.normal.dot(shift);  // n·(x − t) = d
        } else if constexpr (std::is_same_v<T, Sphere>) {
          vec(e, "center", s.center + shift);
          e << YAML::Key << "radius" << YAML::Value << s.radius;
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          vec(e, "axis", s.axis);
          vec(e, "point", s.point + shift);
          e << YAML::Key << "radius" << YAML::Value << s.radius;
        } else if constexpr (std::is_same_v<T, Torus>) {
          vec(e, "axis", s.axis);
          vec(e, "center", s.center + shift);
          e << YAML::Key << "major_radius" << YAML::Value << s.major_radius;
          e << YAML::Key << "minor_radius" << YAML::Value << s.minor_radius;
        } else {
          vec(e, "axis", s.axis);
          vec(e, "apex", s.apex + shift);
          e << YAML::Key << "half_angle" << YAML::Value << s.half_angle;
        }
      },
      p);
}

/// A fitted kinematic surface: its motion, its profile as a list of [a, b] points in its profile
/// plane (`profile_coordinates` says which: kinematic_surface.h) and its fit's figures.
void kinematicSurface(YAML::Emitter& e, const KinematicFit& k, const Eigen::Vector3d& shift) {
  const KinematicSurface& s = k.surface;
  e << YAML::Key << "kinematic" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "class" << YAML::Value << std::string(kinematicTypeName(s.type));
  vec(e, "axis", s.axis);
  vec(e, "point", s.point + shift);
  e << YAML::Key << "pitch" << YAML::Value << s.pitch;
  if (s.type != KinematicType::revolution)
    vec(e, "reference", s.reference);
  if (s.type == KinematicType::helix)
    e << YAML::Key << "cut" << YAML::Value << s.cut;
  e << YAML::Key << "profile_coordinates" << YAML::Value
    << (s.type == KinematicType::revolution
            ? "[height along the axis from point, distance from the axis]"
        : s.type == KinematicType::extrusion
            ? "[along reference, along axis x reference], from point"
            : "[height - pitch * angle from reference, wrapped into [cut, cut + 2 pi |pitch|), "
              "distance from the axis]");
  e << YAML::Key << "profile_closed" << YAML::Value << s.profile.closed;
  e << YAML::Key << "profile" << YAML::Value << YAML::BeginSeq;
  for (const Eigen::Vector2d& v : s.profile.vertices)
    e << YAML::Flow << YAML::BeginSeq << v.x() << v.y() << YAML::EndSeq;
  e << YAML::EndSeq;
  e << YAML::Key << "rms_distance" << YAML::Value << k.rms_distance;
  e << YAML::Key << "used_points" << YAML::Value << k.used_points;
  e << YAML::Key << "parameters" << YAML::Value << parameterCount(s);
  e << YAML::EndMap;
}

}  // namespace

std::string primitivesYaml(const std::vector<PrimitiveRecord>& records, const std::string& source,
                           const Eigen::Vector3d& shift) {
  YAML::Emitter e;
  e.SetDoublePrecision(17);
  e << YAML::BeginMap;
  e << YAML::Key << "source" << YAML::Value << source;
  e << YAML::Key << "units" << YAML::Value << "lengths in the cloud's units, angles in radians";
  if (shift != Eigen::Vector3d::Zero())
    vec(e, "global_shift", shift);  // subtracted while computing; the positions below include it
  e << YAML::Key << "primitives" << YAML::Value << YAML::BeginSeq;
  for (const auto& r : records) {
    e << YAML::BeginMap;
    e << YAML::Key << "id" << YAML::Value << r.id;
    if (r.label)
      e << YAML::Key << "label" << YAML::Value << *r.label;
    if (!r.fitted) {
      const bool bad = r.slippage && r.slippage->type == SlippageType::degenerate;
      e << YAML::Key << "type" << YAML::Value
        << std::string(r.slippage ? slippageTypeName(r.slippage->type)
                                  : std::string_view("unknown"));
      e << YAML::Key << "status" << YAML::Value << (bad ? "degenerate" : "not_fitted");
      if (bad)
        e << YAML::Key << "reason" << YAML::Value << r.slippage->reason;
    } else {
      e << YAML::Key << "type" << YAML::Value << std::string(primitiveTypeName(r.fit.type));
      e << YAML::Key << "status" << YAML::Value << std::string(fitStatusName(r.fit.status));
    }
    if (r.slippage) {
      const SlippageResult& sl = *r.slippage;
      e << YAML::Key << "slippage_type" << YAML::Value << std::string(slippageTypeName(sl.type));
      e << YAML::Key << "slippable_motions" << YAML::Value << sl.motions;
      e << YAML::Key << "spectrum" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (int j = 0; j < 6; ++j)
        e << sl.spectrum(j);
      e << YAML::EndSeq;
      if (sl.axis)
        vec(e, "slippage_axis", *sl.axis);
      if (sl.point)
        vec(e, "slippage_point", *sl.point + shift);
      if (sl.center)
        vec(e, "slippage_center", *sl.center + shift);
      if (sl.normal)
        vec(e, "slippage_normal", *sl.normal);
      if (sl.pitch)
        e << YAML::Key << "pitch" << YAML::Value << *sl.pitch;
      e << YAML::Key << "slippage_gap" << YAML::Value << sl.gap;
      e << YAML::Key << "slippage_threshold" << YAML::Value << sl.threshold;
      // The motion that slides the surface along itself, whatever the primitive (none for a
      // general surface): the class, its axis and a point on it, and the screw's pitch.
      if (r.kinematic) {
        kinematicSurface(e, *r.kinematic, shift);
      } else if (sl.type != SlippageType::degenerate) {
        e << YAML::Key << "kinematic" << YAML::Value << YAML::BeginMap;
        e << YAML::Key << "class" << YAML::Value << std::string(slippageTypeName(sl.type));
        if (sl.axis)
          vec(e, "axis", *sl.axis);
        else if (sl.normal)
          vec(e, "normal", *sl.normal);
        if (sl.point)
          vec(e, "point", *sl.point + shift);
        else if (sl.center)
          vec(e, "point", *sl.center + shift);
        if (sl.axis)
          e << YAML::Key << "pitch" << YAML::Value << sl.pitch.value_or(0.0);
        e << YAML::EndMap;
      }
    }
    if (!r.fitted) {
    } else if (!r.fit.ok()) {
      e << YAML::Key << "reason" << YAML::Value << r.fit.reason;
    } else {
      parameters(e, r.fit.refined, shift);
      e << YAML::Key << "inliers" << YAML::Value << r.inliers;
      e << YAML::Key << "inlier_distance" << YAML::Value << r.inlier_distance;
      e << YAML::Key << "rms_distance" << YAML::Value << r.fit.rms_distance;
      e << YAML::Key << "max_distance" << YAML::Value << r.fit.max_distance;
      e << YAML::Key << "used_points" << YAML::Value << r.fit.used_points;
      e << YAML::Key << "loss_algebraic" << YAML::Value << r.fit.loss_algebraic;
      e << YAML::Key << "loss_refined" << YAML::Value << r.fit.loss_refined;
      e << YAML::Key << "reciprocal_condition" << YAML::Value << r.fit.reciprocal_condition;
      e << YAML::Key << "algebraic" << YAML::Value << YAML::BeginMap;
      parameters(e, r.fit.algebraic, shift);
      e << YAML::EndMap;
    }
    for (const auto& [k, v] : r.extra)
      e << YAML::Key << k << YAML::Value << v;
    e << YAML::EndMap;
  }
  e << YAML::EndSeq << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

std::optional<Primitive> readPrimitive(const YAML::Node& entry, const Eigen::Vector3d& shift) {
  try {
    if (entry["status"] && entry["status"].as<std::string>() != "ok")
      return std::nullopt;
    const auto v = [&](const char* key) {
      const YAML::Node n = entry[key];
      return Eigen::Vector3d(n[0].as<double>(), n[1].as<double>(), n[2].as<double>());
    };
    const auto x = [&](const char* key) { return entry[key].as<double>(); };
    const std::string type = entry["type"].as<std::string>();
    if (type == primitiveTypeName(PrimitiveType::plane)) {
      const Eigen::Vector3d n = v("normal");
      return Plane{n, x("d") - n.dot(shift)};
    }
    if (type == primitiveTypeName(PrimitiveType::sphere))
      return Sphere{v("center") - shift, x("radius")};
    if (type == primitiveTypeName(PrimitiveType::cylinder))
      return Cylinder{v("axis"), v("point") - shift, x("radius")};
    if (type == primitiveTypeName(PrimitiveType::cone))
      return Cone{v("axis"), v("apex") - shift, x("half_angle")};
    if (type == primitiveTypeName(PrimitiveType::torus))
      return Torus{v("axis"), v("center") - shift, x("major_radius"), x("minor_radius")};
  } catch (const YAML::Exception&) {
  }
  return std::nullopt;
}

}  // namespace slipfit::pipeline
