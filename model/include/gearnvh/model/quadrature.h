// Gauss–Legendre quadrature on [a, b] (setup-time integrals: tooth energies, segment means).
#pragma once

#include <cstddef>
#include <vector>

namespace gearnvh {

struct GaussLegendreRule {
  std::vector<double> nodes;    // on [-1, 1]
  std::vector<double> weights;  // sum to 2
};

// The n-point rule (n >= 1), nodes from Newton's method on P_n; exact for degree 2n - 1.
GaussLegendreRule MakeGaussLegendre(int n);

// Integrates f over [a, b] with the given rule.
template <typename F>
double Integrate(const GaussLegendreRule& rule, double a, double b, F&& f) {
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0.0;
  for (std::size_t i = 0; i < rule.nodes.size(); ++i)
    sum += rule.weights[i] * f(mid + half * rule.nodes[i]);
  return sum * half;
}

}  // namespace gearnvh
