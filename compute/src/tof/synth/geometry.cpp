#include "geometry.hpp"

namespace trailscope::tof::synth {

Primitive make_ellipsoid(const Vec3& centre, const Mat3& rotation, const Vec3& semi_axes) {
  Primitive p;
  p.shape = Primitive::Shape::ellipsoid;
  p.c = centre;
  p.M = rotation * semi_axes.cwiseInverse().cwiseAbs2().asDiagonal() * rotation.transpose();
  p.Mc = p.M * centre;
  p.cmc = centre.dot(p.Mc) - 1.0;
  return p;
}

Primitive make_capsule(const Vec3& a, const Vec3& b, double radius) {
  Primitive p;
  p.shape = Primitive::Shape::capsule;
  p.a = a;
  p.b = b;
  p.ba = b - a;
  p.baba = p.ba.squaredNorm();
  p.r = radius;
  p.baoa = -p.ba.dot(a);
  p.oaoa = a.squaredNorm();
  p.qc = p.baba * p.oaoa - p.baoa * p.baoa - radius * radius * p.baba;
  p.aa_rr = a.squaredNorm() - radius * radius;
  p.bb_rr = b.squaredNorm() - radius * radius;
  return p;
}

Primitive make_plane(const Vec3& normal, double dist) {
  Primitive p;
  p.shape = Primitive::Shape::plane;
  p.n = normal.normalized();
  p.dist = dist;
  return p;
}

namespace {
// Where q2 a^2 + q1 a + q0 >= 0 for a quadratic that opens downwards; false if nowhere.
bool nonnegative_interval(double q2, double q1, double q0, double margin, double* lo, double* hi) {
  const double scale = std::abs(q2) + std::abs(q1) + std::abs(q0);
  if (!(q2 < -1e-12 * scale)) {  // not an ellipse-like silhouette: do not cull
    *lo = -kNoHit, *hi = kNoHit;
    return true;
  }
  const double disc = q1 * q1 - 4 * q2 * q0;
  if (disc < 0) return false;
  const double root = std::sqrt(disc), r1 = (-q1 + root) / (2 * q2), r2 = (-q1 - root) / (2 * q2);
  *lo = std::min(r1, r2) - margin;
  *hi = std::max(r1, r2) + margin;
  return true;
}
}  // namespace

bool row_interval(const Primitive& p, double b, double margin, double* a_lo, double* a_hi) {
  switch (p.shape) {
    case Primitive::Shape::ellipsoid: {
      // d = d0 + a ex with d0 = (0, b, 1): A = d^T M d, B = d^T M c, disc = B^2 - A cmc.
      const Vec3 d0(0, b, 1);
      const double A2 = p.M(0, 0), A1 = 2 * p.M.row(0).dot(d0), A0 = d0.dot(p.M * d0);
      const double B1 = p.Mc.x(), B0 = d0.dot(p.Mc);
      return nonnegative_interval(B1 * B1 - A2 * p.cmc, 2 * B1 * B0 - A1 * p.cmc, B0 * B0 - A0 * p.cmc,
                                  margin, a_lo, a_hi);
    }
    case Primitive::Shape::capsule: {
      // The capsule lies inside its infinite cylinder, whose discriminant h(a) = qb^2 - qa qc is quadratic.
      const double P1 = p.ba.x(), P0 = p.ba.y() * b + p.ba.z();
      const double qa2 = p.baba - P1 * P1, qa1 = -2 * P1 * P0, qa0 = p.baba * (b * b + 1) - P0 * P0;
      const double R1 = -p.a.x(), R0 = -(p.a.y() * b + p.a.z());
      const double Q1 = p.baba * R1 - p.baoa * P1, Q0 = p.baba * R0 - p.baoa * P0;
      return nonnegative_interval(Q1 * Q1 - p.qc * qa2, 2 * Q1 * Q0 - p.qc * qa1, Q0 * Q0 - p.qc * qa0,
                                  margin, a_lo, a_hi);
    }
    case Primitive::Shape::plane:
      *a_lo = -kNoHit, *a_hi = kNoHit;
      return true;
  }
  return true;
}

void set_screen_rect(Primitive& p, double fx, double fy, double cx, double cy, int width, int height) {
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  switch (p.shape) {
    case Primitive::Shape::ellipsoid: {
      // The extent of x^T M x = 1 along axis i is sqrt((M^-1)_ii).
      const Vec3 ext = p.M.inverse().diagonal().cwiseSqrt();
      lo = p.c - ext;
      hi = p.c + ext;
      break;
    }
    case Primitive::Shape::capsule:
      lo = p.a.cwiseMin(p.b) - Vec3::Constant(p.r);
      hi = p.a.cwiseMax(p.b) + Vec3::Constant(p.r);
      break;
    case Primitive::Shape::plane:
      lo = hi = Vec3::Zero();
      p.u0 = 0, p.u1 = width - 1, p.v0 = 0, p.v1 = height - 1;
      return;
  }
  if (hi.z() <= kNearMm) {  // wholly behind the camera: never hit
    p.u0 = 0, p.u1 = -1, p.v0 = 0, p.v1 = -1;
    return;
  }
  // Hits nearer than kNearMm do not count, so the box may be cut there: its projection stays bounded
  // (and, for a leg reaching past the camera at the side, small).
  lo.z() = std::max(lo.z(), kNearMm);
  double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
  for (int i = 0; i < 8; ++i) {
    const Vec3 q((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
    const double u = fx * q.x() / q.z() + cx, v = fy * q.y() / q.z() + cy;
    umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  }
  // The projection of a box in z > 0 is bounded by its projected corners; one pixel of margin covers the
  // sub-pixel rays of flying pixels. Clamp before converting: corners near z = 0 project very far.
  const auto clampd = [](double x, double hi) { return std::clamp(x, -2.0, hi + 2.0); };
  p.u0 = std::max(0, static_cast<int>(std::floor(clampd(umin, width))) - 1);
  p.u1 = std::min(width - 1, static_cast<int>(std::ceil(clampd(umax, width))) + 1);
  p.v0 = std::max(0, static_cast<int>(std::floor(clampd(vmin, height))) - 1);
  p.v1 = std::min(height - 1, static_cast<int>(std::ceil(clampd(vmax, height))) + 1);
}

}  // namespace trailscope::tof::synth
