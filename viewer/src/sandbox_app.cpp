#include "sandbox_app.hpp"

#include <stdexcept>

namespace viewer {

int run_windowed(const SandboxOptions&) { throw std::runtime_error("the windowed sandbox is not built yet; use --headless"); }

}  // namespace viewer
