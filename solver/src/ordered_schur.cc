#include "ordered_schur.h"

#include <algorithm>
#include <cmath>

extern "C" {
// LAPACK (Fortran ABI; trailing hidden string lengths).
void dgees_(const char* jobvs, const char* sort, int (*select)(const double*, const double*),
            const int* n, double* a, const int* lda, int* sdim, double* wr, double* wi, double* vs,
            const int* ldvs, double* work, const int* lwork, int* bwork, int* info, size_t, size_t);
void dtrexc_(const char* compq, const int* n, double* t, const int* ldt, double* q, const int* ldq,
             int* ifst, int* ilst, double* work, int* info, size_t);
}

namespace gearnvh {

OrderedSchur OrderedRealSchur(const Eigen::MatrixXd& A) {
  OrderedSchur s;
  const int e = static_cast<int>(A.rows());
  s.T = A;
  s.U.resize(e, e);
  Eigen::MatrixXd& T = s.T;
  Eigen::VectorXd wr(e), wi(e);
  std::vector<int> bwork(static_cast<size_t>(e));
  int sdim = 0, info = 0, lwork = -1;
  double query = 0.0;
  dgees_("V", "N", nullptr, &e, T.data(), &e, &sdim, wr.data(), wi.data(), s.U.data(), &e, &query,
         &lwork, bwork.data(), &info, 1, 1);
  lwork = std::max(1, static_cast<int>(query));
  std::vector<double> work(static_cast<size_t>(lwork));
  dgees_("V", "N", nullptr, &e, T.data(), &e, &sdim, wr.data(), wi.data(), s.U.data(), &e,
         work.data(), &lwork, bwork.data(), &info, 1, 1);
  if (info != 0) return s;
  auto block_size = [&](int i) { return i + 1 < e && T(i + 1, i) != 0.0 ? 2 : 1; };
  auto block_modulus = [&](int i) {
    return block_size(i) == 1
               ? std::abs(T(i, i))
               : std::sqrt(std::abs(T(i, i) * T(i + 1, i + 1) - T(i, i + 1) * T(i + 1, i)));
  };
  std::vector<double> trexc_work(static_cast<size_t>(e));
  for (int p = 0; p < e;) {
    int best = p;
    for (int i = p; i < e; i += block_size(i)) {
      if (block_modulus(i) > block_modulus(best)) best = i;
    }
    if (best != p) {
      int ifst = best + 1, ilst = p + 1;
      dtrexc_("V", &e, T.data(), &e, s.U.data(), &e, &ifst, &ilst, trexc_work.data(), &info, 1);
      if (info != 0) return s;
    }
    s.block_start.push_back(p);
    s.block_modulus.push_back(block_modulus(p));
    p += block_size(p);
  }
  s.info = OrderedSchur::Info::kSuccess;
  return s;
}

}  // namespace gearnvh
