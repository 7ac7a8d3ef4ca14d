#include "linalg/gmres.hpp"

#include <cmath>
#include <cstddef>

namespace hencky {

bool gmres(const LinearOperator& apply, const LinearOperator& precondition,
           const InnerProduct& dot, const std::vector<double>& b, std::vector<double>& x,
           const GmresOptions& options, int& iterations) {
  const std::size_t n = b.size();
  const int m = options.restart;
  const double rtol = options.rtol;
  const double b_norm = std::sqrt(dot(b, b));
  if (!(b_norm > 0)) return true;
  std::vector<double> r(n);
  apply(x, r);
  for (std::size_t i = 0; i < n; ++i) r[i] = b[i] - r[i];
  for (int cycle = 0; cycle < options.max_cycles; ++cycle) {
    const double beta = std::sqrt(dot(r, r));
    if (beta <= rtol * b_norm) return true;
    std::vector<std::vector<double>> V(1, r), Z;  // the Krylov basis and its M⁻¹ images
    for (double& v : V[0]) v /= beta;
    std::vector<std::vector<double>> H(m + 1, std::vector<double>(m, 0.0));
    std::vector<double> cs(m), sn(m), g(m + 1, 0.0);
    g[0] = beta;
    int j = 0;
    for (; j < m; ++j) {
      Z.emplace_back(n);
      precondition(V[j], Z[j]);
      std::vector<double> w(n);
      apply(Z[j], w);
      ++iterations;
      for (int i = 0; i <= j; ++i) {  // modified Gram–Schmidt
        H[i][j] = dot(w, V[i]);
        for (std::size_t k = 0; k < n; ++k) w[k] -= H[i][j] * V[i][k];
      }
      H[j + 1][j] = std::sqrt(dot(w, w));
      for (int i = 0; i < j; ++i) {  // the earlier rotations on the new column
        const double a = H[i][j], c = H[i + 1][j];
        H[i][j] = cs[i] * a + sn[i] * c;
        H[i + 1][j] = -sn[i] * a + cs[i] * c;
      }
      const double d = std::hypot(H[j][j], H[j + 1][j]);
      cs[j] = H[j][j] / d;
      sn[j] = H[j + 1][j] / d;
      H[j][j] = d;
      H[j + 1][j] = 0;
      g[j + 1] = -sn[j] * g[j];
      g[j] = cs[j] * g[j];
      const bool done = std::abs(g[j + 1]) <= rtol * b_norm;  // |g_{j+1}| is the residual
      if (!done && j + 1 < m) {  // the next basis vector
        V.emplace_back(w);
        const double hn = std::sqrt(dot(w, w));
        if (hn > 0)
          for (double& v : V.back()) v /= hn;
      }
      if (done) {
        ++j;
        break;
      }
    }
    // y from the triangular system H y = g, then x += Z y.
    std::vector<double> y(j);
    for (int i = j - 1; i >= 0; --i) {
      double s = g[i];
      for (int k = i + 1; k < j; ++k) s -= H[i][k] * y[k];
      y[i] = s / H[i][i];
    }
    for (int i = 0; i < j; ++i)
      for (std::size_t k = 0; k < n; ++k) x[k] += y[i] * Z[i][k];
    apply(x, r);
    for (std::size_t i = 0; i < n; ++i) r[i] = b[i] - r[i];
  }
  return std::sqrt(dot(r, r)) <= rtol * b_norm;
}

}  // namespace hencky
