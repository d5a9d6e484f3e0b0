#include "internal/motion_filter.h"

#include <algorithm>
#include <cmath>

namespace specht::track::internal {
namespace {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;

// Joseph-form update for a filter whose first two states are the position:
//   K = P Hᵀ S⁻¹, x += K ν, P = (I − K H) P (I − K H)ᵀ + K R Kᵀ (stays symmetric PSD).
template <int N>
void PositionUpdate(Eigen::Matrix<double, N, 1>& x, Eigen::Matrix<double, N, N>& p, const Vec2& nu, const Mat2& r) {
  Eigen::Matrix<double, 2, N> h = Eigen::Matrix<double, 2, N>::Zero();
  h(0, 0) = h(1, 1) = 1;
  const Mat2 s = h * p * h.transpose() + r;
  const Eigen::Matrix<double, N, 2> k = p * h.transpose() * s.inverse();
  x += k * nu;
  const Eigen::Matrix<double, N, N> ikh = Eigen::Matrix<double, N, N>::Identity() - k * h;
  p = ikh * p * ikh.transpose() + k * r * k.transpose();
}

class ConstantVelocity final : public MotionFilter {
 public:
  ConstantVelocity(const Vec4& x, const Mat4& p) : x_(x), p_(p) {}
  std::unique_ptr<MotionFilter> Clone() const override { return std::make_unique<ConstantVelocity>(*this); }
  void Predict(double dt, double accel_sigma, double) override {
    Mat4 f = Mat4::Identity();
    f(0, 2) = f(1, 3) = dt;
    Eigen::Matrix<double, 4, 2> g = Eigen::Matrix<double, 4, 2>::Zero();
    g(0, 0) = g(1, 1) = dt * dt / 2;
    g(2, 0) = g(3, 1) = dt;
    x_ = f * x_;
    p_ = f * p_ * f.transpose() + accel_sigma * accel_sigma * g * g.transpose();
  }
  void Update(const Vec2& z, const Mat2& r) override { PositionUpdate<4>(x_, p_, z - x_.head<2>(), r); }
  Vec2 Position() const override { return x_.head<2>(); }
  Mat2 PositionCovariance() const override { return p_.topLeftCorner<2, 2>(); }
  void Cartesian(Vec4& state, Mat4& covariance) const override { state = x_, covariance = p_; }
  const char* name() const override { return "cv"; }

 private:
  Vec4 x_;
  Mat4 p_;
};

class ConstantTurn final : public MotionFilter {
 public:
  ConstantTurn(const Vec5& x, const Mat5& p) : x_(x), p_(p) {}
  std::unique_ptr<MotionFilter> Clone() const override { return std::make_unique<ConstantTurn>(*this); }

  static Vec5 Propagate(const Vec5& s, double dt) {
    Vec5 o = s;
    const double v = s(2), th = s(3), w = s(4);
    if (std::abs(w) > 1e-6) {
      o(0) += v / w * (std::sin(th + w * dt) - std::sin(th));
      o(1) -= v / w * (std::cos(th + w * dt) - std::cos(th));
    } else {
      o(0) += v * std::cos(th) * dt;
      o(1) += v * std::sin(th) * dt;
    }
    o(3) = th + w * dt;
    return o;
  }

  void Predict(double dt, double accel_sigma, double turn_sigma) override {
    // The Jacobian by central differences: the closed form has a removable
    // singularity at ω = 0 that the differences handle without a special case.
    Mat5 f;
    for (int i = 0; i < 5; ++i) {
      Vec5 d = Vec5::Zero();
      d(i) = 1e-6;
      f.col(i) = (Propagate(x_ + d, dt) - Propagate(x_ - d, dt)) / 2e-6;
    }
    const double c = std::cos(x_(3)), s = std::sin(x_(3));
    Eigen::Matrix<double, 5, 2> g = Eigen::Matrix<double, 5, 2>::Zero();
    g(0, 0) = dt * dt / 2 * c;
    g(1, 0) = dt * dt / 2 * s;
    g(2, 0) = dt;
    g(3, 1) = dt * dt / 2;
    g(4, 1) = dt;
    const Mat2 q = Eigen::Vector2d(accel_sigma * accel_sigma, turn_sigma * turn_sigma).asDiagonal();
    x_ = Propagate(x_, dt);
    p_ = f * p_ * f.transpose() + g * q * g.transpose();
    // Negative speed is the same motion with the heading turned around.
    if (x_(2) < 0) {
      x_(2) = -x_(2);
      x_(3) += M_PI;
      Mat5 flip = Mat5::Identity();
      flip(2, 2) = -1;
      p_ = flip * p_ * flip.transpose();
    }
    x_(3) = std::remainder(x_(3), 2 * M_PI);
  }
  void Update(const Vec2& z, const Mat2& r) override {
    PositionUpdate<5>(x_, p_, z - x_.head<2>(), r);
    x_(3) = std::remainder(x_(3), 2 * M_PI);
  }
  Vec2 Position() const override { return x_.head<2>(); }
  Mat2 PositionCovariance() const override { return p_.topLeftCorner<2, 2>(); }
  void Cartesian(Vec4& state, Mat4& covariance) const override {
    const double v = x_(2), c = std::cos(x_(3)), s = std::sin(x_(3));
    state << x_(0), x_(1), v * c, v * s;
    Eigen::Matrix<double, 4, 5> j = Eigen::Matrix<double, 4, 5>::Zero();
    j(0, 0) = j(1, 1) = 1;
    j(2, 2) = c, j(2, 3) = -v * s;
    j(3, 2) = s, j(3, 3) = v * c;
    covariance = j * p_ * j.transpose();
  }
  const char* name() const override { return "ct"; }

 private:
  Vec5 x_;
  Mat5 p_;
};

}  // namespace

std::unique_ptr<MotionFilter> MakeConstantVelocity(const Vec2& position, const Mat2& position_cov, double speed_sigma) {
  Vec4 x;
  x << position, 0, 0;
  Mat4 p = Mat4::Zero();
  p.topLeftCorner<2, 2>() = position_cov;
  p(2, 2) = p(3, 3) = speed_sigma * speed_sigma;
  return std::make_unique<ConstantVelocity>(x, p);
}

std::unique_ptr<MotionFilter> MakeConstantTurn(const MotionFilter& from, double turn_rate_sigma) {
  Vec4 c;
  Mat4 pc;
  from.Cartesian(c, pc);
  const double v = std::hypot(c(2), c(3));
  const double vs = std::max(v, 1e-3);
  // (v, θ) from (vx, vy): J = [[vx/v, vy/v], [−vy/v², vx/v²]].
  Eigen::Matrix<double, 5, 4> j = Eigen::Matrix<double, 5, 4>::Zero();
  j(0, 0) = j(1, 1) = 1;
  j(2, 2) = c(2) / vs, j(2, 3) = c(3) / vs;
  j(3, 2) = -c(3) / (vs * vs), j(3, 3) = c(2) / (vs * vs);
  Vec5 x;
  x << c(0), c(1), v, std::atan2(c(3), c(2)), 0;
  Mat5 p = j * pc * j.transpose();
  p(3, 3) = std::min(p(3, 3), M_PI * M_PI);
  p(4, 4) = turn_rate_sigma * turn_rate_sigma;
  return std::make_unique<ConstantTurn>(x, p);
}

}  // namespace specht::track::internal
