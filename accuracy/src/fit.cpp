#include "granular/accuracy/fit.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace granular::accuracy {

LineFit fit_line(std::span<const double> x, std::span<const double> y) {
  LineFit f;
  const std::size_t n = std::min(x.size(), y.size());
  if (n < 2) return f;
  double sx = 0, sy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sx += x[i];
    sy += y[i];
  }
  const double mx = sx / double(n), my = sy / double(n);
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 1e-300) return f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  f.r2 = syy > 0 ? (sxy * sxy) / (sxx * syy) : 1;
  f.ok = true;
  return f;
}

PowerFit fit_power(std::span<const double> x, std::span<const double> y) {
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i)
    if (x[i] > 0 && y[i] > 0) {
      lx.push_back(std::log(x[i]));
      ly.push_back(std::log(y[i]));
    }
  PowerFit p;
  const LineFit l = fit_line(lx, ly);
  if (!l.ok) return p;
  p.prefactor = std::exp(l.intercept);
  p.exponent = l.slope;
  p.r2 = l.r2;
  p.ok = true;
  return p;
}

BeverlooFit fit_beverloo(std::span<const double> d, std::span<const double> w) {
  BeverlooFit best;
  const std::size_t n = std::min(d.size(), w.size());
  if (n < 3) return best;
  const double d_min = *std::min_element(d.begin(), d.begin() + std::ptrdiff_t(n));
  double best_residual = 0;
  for (double k = 0; k <= d_min - 0.5; k += 0.01) {
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i) x[i] = d[i] - k;
    const PowerFit p = fit_power(x, std::span<const double>(w.data(), n));
    if (!p.ok) continue;
    double residual = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = std::log(w[i]) - std::log(p.prefactor) - p.exponent * std::log(x[i]);
      residual += e * e;
    }
    if (!best.ok || residual < best_residual) {
      best = {p.prefactor, k, p.exponent, p.r2, true};
      best_residual = residual;
    }
  }
  return best;
}

}  // namespace granular::accuracy
