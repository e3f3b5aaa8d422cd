// Gauss–Legendre quadrature on [a, b] (setup-time integrals: tooth energies, segment means).
#pragma once

#include <array>
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

// Integrates the N components of f (which returns std::array<double, N>) over [a, b] in one pass
// over the nodes: for integrands that share costly terms. Each component is summed as Integrate
// sums it.
template <std::size_t N, typename F>
std::array<double, N> IntegrateComponents(const GaussLegendreRule& rule, double a, double b,
                                          F&& f) {
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  std::array<double, N> sum{};
  for (std::size_t i = 0; i < rule.nodes.size(); ++i) {
    const std::array<double, N> value = f(mid + half * rule.nodes[i]);
    for (std::size_t k = 0; k < N; ++k) sum[k] += rule.weights[i] * value[k];
  }
  for (double& s : sum) s *= half;
  return sum;
}

}  // namespace gearnvh
