#include "gearnvh/model/tooth_stiffness.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "gearnvh/model/gear_geometry.h"

namespace gearnvh {
namespace {

// Sainsot et al. (2004) polynomial coefficients A..F for L*, M*, P*, Q*.
constexpr double kSainsot[4][6] = {
    {-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045},
    {60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086},
    {-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236},
    {-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904},
};

double SainsotFit(const double c[6], double h_f, double theta_f) {
  return c[0] / (theta_f * theta_f) + c[1] * h_f * h_f + c[2] * h_f / theta_f + c[3] / theta_f +
         c[4] * h_f + c[5];
}

// The fit's range (Sainsot et al. 2004 cover h_f 1.4-7; theta_f is gearnvh's conservative
// envelope, see docs/mesh-stiffness.md); outside it the fit is evaluated at the nearest point.
constexpr double kHfMin = 1.4, kHfMax = 7.0;
constexpr double kThetaMin = 0.01, kThetaMax = 0.3;

}  // namespace

ToothStiffnessModel::ToothStiffnessModel(const GearSpec& gear, const Material& material)
    : ToothStiffnessModel(gear, material, static_cast<double>(gear.teeth)) {}

ToothStiffnessModel::ToothStiffnessModel(const GearSpec& gear, const Material& material,
                                         double teeth)
    : E_(material.youngs_modulus),
      G_(material.youngs_modulus / (2.0 * (1.0 + material.poisson_ratio))),
      L_(gear.face_width),
      rule_(MakeGaussLegendre(48)) {
  const double a0 = gear.pressure_angle;
  const double pitch = 0.5 * gear.module * teeth;
  r_b_ = pitch * std::cos(a0);
  r_f_ = pitch - (gear.dedendum_coefficient - gear.profile_shift) * gear.module;
  alpha2_ = std::numbers::pi / (2.0 * teeth) + Involute(a0) +
            2.0 * gear.profile_shift * std::tan(a0) / teeth;
  if (r_b_ > r_f_) {
    alpha_start_ = -alpha2_;
    straight_half_thickness_ = r_b_ * std::sin(alpha2_);
    const double hb = straight_half_thickness_;
    x_root_straight_ = std::sqrt(std::max(r_f_ * r_f_ - hb * hb, 0.0));
    theta_f_ = std::asin(std::min(hb / r_f_, 1.0));
  } else {
    // Involute cut at the root circle: r(alpha)^2 = r_b^2 (1 + (alpha + alpha2)^2) = r_f^2.
    alpha_start_ = std::sqrt(r_f_ * r_f_ / (r_b_ * r_b_) - 1.0) - alpha2_;
    theta_f_ = alpha2_ - Involute(std::acos(r_b_ / r_f_));
  }
  const double bore_radius = 0.5 * gear.bore_diameter;
  // A solid gear (no bore) is taken at the fit's largest h_f: the body is stiffest there.
  h_f_ = bore_radius > 0.0 ? r_f_ / bore_radius : kHfMax;
  // Outside its range the polynomial fit diverges (1/theta_f^2 terms: a 2000-tooth wheel would get
  // a body compliance two decades too large). The fallback evaluates the fit at the nearest point
  // of its range: a thicker rim than h_f = 7 is as stiff as h_f = 7 (the body stiffness saturates
  // as the bore shrinks), and a tooth narrower than theta_f = 0.01 rad sits on a body that is
  // locally a rack, as it is at theta_f = 0.01 (~150 teeth).
  const double h_fit = std::clamp(h_f_, kHfMin, kHfMax);
  const double theta_fit = std::clamp(theta_f_, kThetaMin, kThetaMax);
  fillet_L_ = SainsotFit(kSainsot[0], h_fit, theta_fit);
  fillet_M_ = SainsotFit(kSainsot[1], h_fit, theta_fit);
  fillet_P_ = SainsotFit(kSainsot[2], h_fit, theta_fit);
  fillet_Q_ = SainsotFit(kSainsot[3], h_fit, theta_fit);
  if (h_fit != h_f_) {
    std::ostringstream w;
    w << "gear body outside the fillet-foundation fit (h_f = r_f/r_bore = " << h_f_
      << ", fit range " << kHfMin << " to " << kHfMax
      << "): body compliance taken at h_f = " << h_fit;
    warnings_.push_back(w.str());
  }
  if (theta_fit != theta_f_) {
    std::ostringstream t;
    t << "tooth root outside the fillet-foundation fit (theta_f = " << theta_f_
      << " rad, fit range " << kThetaMin << " to " << kThetaMax
      << " rad): body compliance taken at theta_f = " << theta_fit << " rad";
    warnings_.push_back(t.str());
  }
}

ToothCompliance ToothStiffnessModel::AtRoll(double roll) const {
  return AtForceAngle(roll / r_b_ - alpha2_);
}

ToothCompliance ToothStiffnessModel::AtForceAngle(double alpha1) const {
  const double c = std::cos(alpha1), s = std::sin(alpha1);
  const double x_p = r_b_ * ((alpha1 + alpha2_) * s + c), h_p = r_b_ * ((alpha1 + alpha2_) * c - s);

  ToothCompliance out;
  // Involute part: the three integrands share x(a), h(a) and dx/da, one pass over the nodes (their
  // sines and cosines were most of a mesh's build).
  if (alpha1 > alpha_start_) {
    const auto [bending, shear, axial] =
        IntegrateComponents<3>(rule_, alpha_start_, alpha1, [&](double a) {
          const double sin_a = std::sin(a), cos_a = std::cos(a);
          const double x = r_b_ * ((a + alpha2_) * sin_a + cos_a);
          const double h = r_b_ * ((a + alpha2_) * cos_a - sin_a);
          const double dx = r_b_ * (a + alpha2_) * cos_a;
          const double area = 2.0 * h * L_;
          const double moment = c * (x_p - x) - s * h_p;
          const double inertia = 2.0 * h * h * h * L_ / 3.0;
          return std::array<double, 3>{moment * moment / (E_ * inertia) * dx,
                                       1.2 * c * c / (G_ * area) * dx, s * s / (E_ * area) * dx};
        });
    out.bending = bending;
    out.shear = shear;
    out.axial = axial;
  }
  // Straight part below the base circle: constant section, closed form.
  if (straight_half_thickness_ > 0.0) {
    const double h = straight_half_thickness_;
    const double x0 = x_root_straight_, x1 = r_b_ * std::cos(alpha2_);
    const double inertia = 2.0 * h * h * h * L_ / 3.0, area = 2.0 * h * L_;
    // ∫ (c (x_p - x) - s h_p)^2 dx = [(m0)^3 - (m1)^3] / (3 c), m(x) = c (x_p - x) - s h_p.
    const double m0 = c * (x_p - x0) - s * h_p, m1 = c * (x_p - x1) - s * h_p;
    const double bend_integral =
        std::abs(c) > 1e-12 ? (m0 * m0 * m0 - m1 * m1 * m1) / (3.0 * c) : m0 * m0 * (x1 - x0);
    out.bending += bend_integral / (E_ * inertia);
    out.shear += 1.2 * c * c * (x1 - x0) / (G_ * area);
    out.axial += s * s * (x1 - x0) / (E_ * area);
  }
  // Gear body.
  const double u = (x_p - r_f_) / (2.0 * r_f_ * theta_f_);
  out.fillet = c * c / (E_ * L_) *
               (fillet_L_ * u * u + fillet_M_ * u +
                fillet_P_ * (1.0 + fillet_Q_ * std::tan(alpha1) * std::tan(alpha1)));
  return out;
}

double HertzContactStiffness(const Material& a, const Material& b, double face_width) {
  const double ca = (1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus;
  const double cb = (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus;
  return std::numbers::pi * face_width / (2.0 * (ca + cb));
}

}  // namespace gearnvh
