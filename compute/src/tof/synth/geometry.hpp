#pragma once
// Analytic surfaces for the synthetic ToF camera, in camera coordinates. Every ray starts at the camera
// centre (the origin) with direction d = ((u - cx) / fx, (v - cy) / fy, 1), so the ray parameter t of a
// hit IS its depth z in mm. Internal to compute/src/tof/synth.
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace trailscope::tof::synth {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

inline constexpr double kNoHit = std::numeric_limits<double>::infinity();
/// Hits nearer than this (mm) are ignored: nothing in the scenes comes this close to the lens (the robot
/// stops at ~150 mm), and the near limit keeps the screen rectangles of legs that reach past the camera
/// bounded.
inline constexpr double kNearMm = 10.0;

/// What a pixel can see. Teats and cups carry their teat index in `teat`.
enum class Object : std::uint8_t { teat, cup, udder, body, leg, tail, hose, wall, none };

struct Primitive {
  enum class Shape : std::uint8_t { ellipsoid, capsule, plane } shape = Shape::capsule;
  Object object = Object::none;
  std::int8_t teat = -1;
  float reflectivity = 0.5f;
  // ellipsoid: (x - c)^T M (x - c) = 1; Mc = M c and cmc = c^T M c - 1 are precomputed.
  Vec3 c = Vec3::Zero();
  Mat3 M = Mat3::Identity();
  Vec3 Mc = Vec3::Zero();
  double cmc = 0;
  // capsule: segment a -> b, radius r; with the ray origin 0 the terms baba = |b - a|^2,
  // baoa = (b - a) . (-a), oaoa = |a|^2 and qc (the constant of the cylinder quadratic) are per primitive.
  Vec3 a = Vec3::Zero(), b = Vec3::Zero(), ba = Vec3::Zero();
  double r = 0, baba = 0, baoa = 0, oaoa = 0, qc = 0, aa_rr = 0, bb_rr = 0;
  // plane: n . x = dist
  Vec3 n = Vec3::UnitZ();
  double dist = 0;
  // Conservative screen rectangle, inclusive, px.
  int u0 = 0, u1 = -1, v0 = 0, v1 = -1;
};

Primitive make_ellipsoid(const Vec3& centre, const Mat3& rotation, const Vec3& semi_axes);
Primitive make_capsule(const Vec3& a, const Vec3& b, double radius);
Primitive make_plane(const Vec3& normal, double dist);

/// Fills the primitive's screen rectangle from its bounding box (whole image when the box reaches behind
/// the camera), widened by one pixel for the sub-pixel rays of flying pixels.
void set_screen_rect(Primitive& p, double fx, double fy, double cx, double cy, int width, int height);

/// Nearest hit t (= z) > kNearMm of the ray t * d, or kNoHit.
inline double intersect(const Primitive& p, const Vec3& d, double dd) {
  switch (p.shape) {
    case Primitive::Shape::ellipsoid: {
      const Vec3 Md = p.M * d;
      const double A = d.dot(Md), B = d.dot(p.Mc), disc = B * B - A * p.cmc;
      if (disc < 0) return kNoHit;
      const double t = (B - std::sqrt(disc)) / A;
      return t > kNearMm ? t : kNoHit;
    }
    case Primitive::Shape::capsule: {
      // Cylinder about the axis, then the end sphere on the side the hit falls (a capsule is convex, so
      // the first hit is on the body or on exactly that cap). With origin 0: oa = -a.
      const double bard = p.ba.dot(d), rdoa = -d.dot(p.a);
      const double qa = p.baba * dd - bard * bard, qb = p.baba * rdoa - p.baoa * bard;
      const double h = qb * qb - qa * p.qc;
      if (h < 0) return kNoHit;
      // End sphere at `centre` (oc = -centre, so sb = -d . centre and sc = |centre|^2 - r^2).
      const auto sphere = [&](const Vec3& centre, double sc) {
        const double sb = -d.dot(centre), hs = sb * sb - dd * sc;
        if (hs < 0) return kNoHit;
        const double t = (-sb - std::sqrt(hs)) / dd;
        return t > kNearMm ? t : kNoHit;
      };
      if (qa <= 1e-12) return std::min(sphere(p.a, p.aa_rr), sphere(p.b, p.bb_rr));  // ray along the axis
      const double t = (-qb - std::sqrt(h)) / qa, y = p.baoa + t * bard;
      if (y > 0 && y < p.baba) return t > kNearMm ? t : kNoHit;
      return y <= 0 ? sphere(p.a, p.aa_rr) : sphere(p.b, p.bb_rr);
    }
    case Primitive::Shape::plane: {
      const double nd = p.n.dot(d);
      if (std::abs(nd) < 1e-12) return kNoHit;
      const double t = p.dist / nd;
      return t > kNearMm ? t : kNoHit;
    }
  }
  return kNoHit;
}

/// The rays of one image row are d(a) = (a, b, 1) with b fixed. Sets [a_lo, a_hi] to an interval of a
/// outside which no ray of the row can hit p (exactly: where the discriminant of the ellipsoid, or of the
/// capsule's infinite cylinder, is >= 0), widened by `margin`; returns false when no ray of the row hits.
/// Unbounded cases (the silhouette is not an ellipse) give (-inf, inf).
bool row_interval(const Primitive& p, double b, double margin, double* a_lo, double* a_hi);

/// Outward normal (not normalised) at the surface point x of p.
inline Vec3 normal_at(const Primitive& p, const Vec3& x) {
  switch (p.shape) {
    case Primitive::Shape::ellipsoid:
      return p.M * (x - p.c);
    case Primitive::Shape::capsule: {
      const double y = std::clamp((x - p.a).dot(p.ba) / p.baba, 0.0, 1.0);
      return x - (p.a + y * p.ba);
    }
    case Primitive::Shape::plane:
      return p.n;
  }
  return Vec3::UnitZ();
}

}  // namespace trailscope::tof::synth
