#include "poured_cone.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// Dry gravel's angle of repose, the target of the table's gravel (40 +- 2 deg).
constexpr double kGravelReposeDeg = 40;

}  // namespace

TestReport run_gravel_cone_test(const SuiteOptions& o) {
  return run_poured_cone(o, {"gravel_cone", "Poured gravel cone: angle of repose and footprint isotropy", Material::Gravel,
                             "dry gravel", kGravelReposeDeg,
                             "dry gravel (coarse grains rest steeper than sand, about 40 deg for dry gravel: e.g. "
                             "Carrigy, Sedimentology 14 (1970) 147; the suite's target 40 +- 2 deg)"});
}

}  // namespace granular::accuracy
