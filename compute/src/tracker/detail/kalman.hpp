#pragma once
// Constant-velocity Kalman filter of one teat tip in 3D (state: position mm, velocity mm/s). Internal.
#include <Eigen/Dense>

namespace trailscope::tracker::detail {

class TipKalman {
 public:
  using V3 = Eigen::Vector3d;
  void init(const V3& p, const V3& v, double pos_sd, double vel_sd) {
    x_ << p, v;
    P_.setZero();
    P_.topLeftCorner<3, 3>().diagonal().setConstant(pos_sd * pos_sd);
    P_.bottomRightCorner<3, 3>().diagonal().setConstant(vel_sd * vel_sd);
  }
  /// Advances by dt seconds. q: spectral density of white-noise acceleration (mm^2/s^3 units, so that
  /// the position variance grows by q dt^3 / 3 per step).
  void predict(double dt, double q) {
    Eigen::Matrix<double, 6, 6> F = Eigen::Matrix<double, 6, 6>::Identity();
    F.topRightCorner<3, 3>().diagonal().setConstant(dt);
    Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
    const double a = q * dt * dt * dt / 3, b = q * dt * dt / 2, c = q * dt;
    for (int i = 0; i < 3; ++i) {
      Q(i, i) = a;
      Q(i, i + 3) = Q(i + 3, i) = b;
      Q(i + 3, i + 3) = c;
    }
    x_ = F * x_;
    P_ = F * P_ * F.transpose() + Q;
  }
  /// Fuses a position measurement with standard deviation r (mm) on each axis.
  void update(const V3& z, double r) {
    const Eigen::Matrix3d S = P_.topLeftCorner<3, 3>() + Eigen::Matrix3d::Identity() * (r * r);
    const Eigen::Matrix<double, 6, 3> K = P_.leftCols<3>() * S.inverse();
    x_ += K * (z - x_.head<3>());
    P_ -= K * P_.topRows<3>();
  }
  /// Moves the position (keeping velocity) — an occluded teat carried by its neighbours.
  void set_position(const V3& p) { x_.head<3>() = p; }
  V3 position() const { return x_.head<3>(); }
  V3 velocity() const { return x_.tail<3>(); }

 private:
  Eigen::Matrix<double, 6, 1> x_ = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> P_ = Eigen::Matrix<double, 6, 6>::Identity();
};

}  // namespace trailscope::tracker::detail
