#include "poured_cone.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

TestReport run_cone_test(const SuiteOptions& o) {
  return run_poured_cone(o, {"cone", "Poured cone: angle of repose and footprint isotropy", Material::Granular,
                             o.material.name, o.material.repose_deg,
                             o.material.name +
                                 " (dry sand 30-35 deg, glass beads 22-25 deg: e.g. Al-Hashemi & Al-Amoudi, Powder Technol. 330 (2018) 397)"});
}

}  // namespace granular::accuracy
