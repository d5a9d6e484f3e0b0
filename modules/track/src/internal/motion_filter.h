// Kalman filters behind the tracker (see tracker.h for the models). Both expose the
// same measurement side: the position is observed directly, z = H x + r.
#pragma once

#include <Eigen/Dense>
#include <memory>

namespace specht::track::internal {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;

class MotionFilter {
 public:
  virtual ~MotionFilter() = default;
  virtual std::unique_ptr<MotionFilter> Clone() const = 0;
  virtual void Predict(double dt, double accel_sigma, double turn_sigma) = 0;
  // Standard update with the position measurement z, covariance r.
  virtual void Update(const Vec2& z, const Mat2& r) = 0;
  virtual Vec2 Position() const = 0;
  virtual Mat2 PositionCovariance() const = 0;
  // (x, y, vx, vy) and its covariance (first-order for the ct state).
  virtual void Cartesian(Vec4& state, Mat4& covariance) const = 0;
  virtual const char* name() const = 0;
};

// Constant velocity, x = (x, y, vx, vy).
std::unique_ptr<MotionFilter> MakeConstantVelocity(const Vec2& position, const Mat2& position_cov, double speed_sigma);
// Constant turn rate and velocity from a cartesian estimate (v = |(vx, vy)|,
// θ = atan2(vy, vx), ω = 0 with σ_ω = turn_rate_sigma).
std::unique_ptr<MotionFilter> MakeConstantTurn(const MotionFilter& from, double turn_rate_sigma);

}  // namespace specht::track::internal
