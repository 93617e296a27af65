#pragma once
/// @file extend/backend_registry.hpp
/// The backends linked into this program beside the CPU one. The core library knows only the CPU
/// backend; a backend library registers itself when the program starts (granular_cuda does, from a
/// static object of its own, so linking granular::granular is all a game does), and World's
/// BackendKind::Auto and BackendKind::Cuda find it here.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "granular/extend/backend_factory.hpp"
#include "granular/world_def.hpp"

namespace granular {

/// A backend a library provides.
struct BackendProvider {
  BackendKind kind = BackendKind::Cuda;  ///< which kind it is (Cuda; Cpu and Auto are not registered)
  std::function<std::string()> unusable_reason;  ///< why it cannot run on this machine now (no
                                                 ///< driver, no device...), empty when it can
  BackendFactory create;                         ///< creates it (called only when usable)
  std::function<std::optional<std::array<std::uint8_t, 16>>()> device_uuid;  ///< the UUID of the
      ///< device it would run on (for graphics interop, external_memory.hpp); nullopt when unusable
};

/// Registers `provider` for its kind, replacing an earlier one of that kind. Throws InvalidArgument
/// for kind Cpu or Auto or when unusable_reason, create or device_uuid is empty. Thread-safe; may be
/// called during static initialisation.
void register_backend(BackendProvider provider);

/// The provider registered for `kind`, or nullopt when none is linked into this program.
std::optional<BackendProvider> registered_backend(BackendKind kind);

}  // namespace granular
