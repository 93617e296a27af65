#include "engine/subsystem.hpp"

namespace engine {

void Subsystem::fixed_update(double) {}

void Subsystem::update(double) {}

void Subsystem::render(double) {}

}  // namespace engine
