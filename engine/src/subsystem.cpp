#include "granular/engine/subsystem.hpp"

namespace granular::engine {

void Subsystem::fixed_update(double) {}

void Subsystem::update(double) {}

void Subsystem::render(double) {}

}  // namespace granular::engine
