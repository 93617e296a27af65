#pragma once
/// @file fit.hpp
/// Least-squares fits the accuracy tests report: straight lines, power laws and Beverloo's law.

#include <span>

namespace granular::accuracy {

/// y = intercept + slope x.
struct LineFit {
  double intercept = 0;  ///< value at x = 0
  double slope = 0;      ///< dy/dx
  double r2 = 0;         ///< coefficient of determination (1 = exact)
  bool ok = false;       ///< false with fewer than 2 points or all x equal
};

/// Ordinary least squares of y against x (equal lengths).
LineFit fit_line(std::span<const double> x, std::span<const double> y);

/// y = prefactor x^exponent, fitted as a line in log-log over the points with x > 0 and y > 0.
struct PowerFit {
  double prefactor = 0;  ///< y at x = 1
  double exponent = 0;   ///< d log y / d log x
  double r2 = 0;         ///< of the log-log line
  bool ok = false;       ///< false with fewer than 2 usable points
};

/// Power-law fit y = C x^n.
PowerFit fit_power(std::span<const double> x, std::span<const double> y);

/// Beverloo's law W = C (D - k)^n.
struct BeverlooFit {
  double prefactor = 0;  ///< C
  double k = 0;          ///< the empty annulus k (cells), searched in [0, min D)
  double exponent = 0;   ///< n
  double r2 = 0;         ///< of the log-log line at the best k
  bool ok = false;       ///< false with fewer than 3 usable points
};

/// Fits W = C (D - k)^n: for k on a 0.01-cell grid in [0, min D - 0.5], a power fit of W against
/// D - k; keeps the k of the smallest log residual.
BeverlooFit fit_beverloo(std::span<const double> d, std::span<const double> w);

}  // namespace granular::accuracy
