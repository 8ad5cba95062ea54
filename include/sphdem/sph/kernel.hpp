#pragma once
// Wendland C2 kernel with support 2h (docs/physics.md). With q = r/h:
//   W(q) = C (2 - q)^4 (1 + 2q)       for q <= 2, else 0
//   C = 7 / (64 pi h^2) in 2D,  21 / (256 pi h^3) in 3D.
// The gradient is written as grad_i W_ij = F(r) (x_i - x_j) with
//   F = (dW/dr) / r = -10 C (2 - q)^3 / h^2,
// which has no 1/r singularity, so coincident particles are harmless.
#include <cmath>
#include <numbers>

namespace sphdem {

template <int D>
class WendlandC2 {
 public:
  explicit WendlandC2(double h) : h_(h), inv_h_(1.0 / h), norm_(normalisation(h)) {}

  double h() const { return h_; }
  double support() const { return 2.0 * h_; }

  double w(double r) const {
    const double q = r * inv_h_;
    if (q >= 2.0) return 0.0;
    const double t = 2.0 - q;
    const double t2 = t * t;
    return norm_ * t2 * t2 * (1.0 + 2.0 * q);
  }

  // (dW/dr) / r, see the header comment.
  double f(double r) const {
    const double q = r * inv_h_;
    if (q >= 2.0) return 0.0;
    const double t = 2.0 - q;
    return -10.0 * norm_ * t * t * t * inv_h_ * inv_h_;
  }

 private:
  static double normalisation(double h) {
    if constexpr (D == 2) {
      return 7.0 / (64.0 * std::numbers::pi * h * h);
    } else {
      return 21.0 / (256.0 * std::numbers::pi * h * h * h);
    }
  }
  double h_, inv_h_, norm_;
};

}  // namespace sphdem
