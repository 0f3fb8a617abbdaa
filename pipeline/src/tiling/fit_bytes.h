#pragma once
/// \file A fit as bytes (packed_values.h), exactly: the joined segments' refits travel from the
/// rank that computed them to every rank that writes their points.

#include "packed_values.h"

#include "slipfit/fitting/primitives.h"
#include "slipfit/fitting/weighted_fit.h"

#include <cstdint>
#include <string>

namespace slipfit::pipeline::tiling {

inline void packVector(std::string& out, const Eigen::Vector3d& v) {
  for (int a = 0; a < 3; ++a)
    pack(out, v[a]);
}
inline Eigen::Vector3d unpackVector(Unpack& in) {
  Eigen::Vector3d v;
  for (int a = 0; a < 3; ++a)
    v[a] = in.next<double>();
  return v;
}

inline void packPrimitive(std::string& out, const Primitive& p) {
  pack(out, static_cast<std::uint8_t>(p.index()));
  if (const auto* q = std::get_if<Plane>(&p)) {
    packVector(out, q->normal);
    pack(out, q->d);
  } else if (const auto* q = std::get_if<Sphere>(&p)) {
    packVector(out, q->center);
    pack(out, q->radius);
  } else if (const auto* q = std::get_if<Cylinder>(&p)) {
    packVector(out, q->axis);
    packVector(out, q->point);
    pack(out, q->radius);
  } else if (const auto* q = std::get_if<Cone>(&p)) {
    packVector(out, q->axis);
    packVector(out, q->apex);
    pack(out, q->half_angle);
  } else if (const auto* q = std::get_if<Torus>(&p)) {
    packVector(out, q->axis);
    packVector(out, q->center);
    pack(out, q->major_radius);
    pack(out, q->minor_radius);
  }
}

inline Primitive unpackPrimitive(Unpack& in) {
  switch (in.next<std::uint8_t>()) {
    case 0: {
      Plane q;
      q.normal = unpackVector(in);
      q.d = in.next<double>();
      return q;
    }
    case 1: {
      Sphere q;
      q.center = unpackVector(in);
      q.radius = in.next<double>();
      return q;
    }
    case 2: {
      Cylinder q;
      q.axis = unpackVector(in);
      q.point = unpackVector(in);
      q.radius = in.next<double>();
      return q;
    }
    case 3: {
      Cone q;
      q.axis = unpackVector(in);
      q.apex = unpackVector(in);
      q.half_angle = in.next<double>();
      return q;
    }
    case 4: {
      Torus q;
      q.axis = unpackVector(in);
      q.center = unpackVector(in);
      q.major_radius = in.next<double>();
      q.minor_radius = in.next<double>();
      return q;
    }
    default:
      throw RunError("a rank's message holds no primitive (ranks of different builds?)");
  }
}

inline void packFit(std::string& out, const FitResult& f) {
  pack(out, f.type);
  pack(out, f.status);
  packText(out, f.reason);
  packPrimitive(out, f.algebraic);
  packPrimitive(out, f.refined);
  for (const double v :
       {f.loss_algebraic, f.loss_refined, f.rms_distance, f.max_distance, f.reciprocal_condition})
    pack(out, v);
  pack(out, static_cast<std::uint64_t>(f.used_points));
  pack(out, f.iterations);
}

inline FitResult unpackFit(Unpack& in) {
  FitResult f;
  f.type = in.next<PrimitiveType>();
  f.status = in.next<FitStatus>();
  f.reason = in.text();
  f.algebraic = unpackPrimitive(in);
  f.refined = unpackPrimitive(in);
  for (double* v : {&f.loss_algebraic, &f.loss_refined, &f.rms_distance, &f.max_distance,
                    &f.reciprocal_condition})
    *v = in.next<double>();
  f.used_points = static_cast<std::size_t>(in.next<std::uint64_t>());
  f.iterations = in.next<int>();
  return f;
}

}  // namespace slipfit::pipeline::tiling
