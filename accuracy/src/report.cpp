#include "granular/accuracy/report.hpp"

#include <cmath>
#include <limits>

namespace granular::accuracy {

double Metric::normalized_error() const {
  if (!std::isfinite(measured)) return std::numeric_limits<double>::infinity();
  return std::abs(error()) / tolerance;
}

double TestReport::mean_normalized_error() const {
  if (metrics.empty()) return 0;
  double sum = 0;
  for (const Metric& m : metrics) sum += m.normalized_error();
  return sum / double(metrics.size());
}

double SuiteReport::seconds() const {
  double s = 0;
  for (const TestReport& t : tests) s += t.seconds;
  return s;
}

double SuiteReport::mean_normalized_error() const {
  if (tests.empty()) return 0;
  double sum = 0;
  int n = 0;
  for (const TestReport& t : tests)
    if (!t.metrics.empty()) {
      sum += t.mean_normalized_error();
      ++n;
    }
  return n ? sum / n : 0;
}

bool SuiteReport::conserved() const {
  for (const TestReport& t : tests)
    if (!t.conserved) return false;
  return true;
}

}  // namespace granular::accuracy
