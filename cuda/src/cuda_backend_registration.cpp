/// @file cuda_backend_registration.cpp
/// Registers the CUDA backend with the core's backend registry (backend_registry.hpp) when the
/// program starts, so World's BackendKind::Auto and BackendKind::Cuda find it. Every program that
/// links granular_cuda keeps this object: the library's link options ask for
/// granular_cuda_backend_registered, which only this file defines.

#include "granular/extend/backend_registry.hpp"
#include "granular_cuda/cuda_backend_factory.hpp"

namespace {

/// The CUDA backend as the registry describes it.
granular::BackendProvider cuda_provider() {
  granular::BackendProvider provider;
  provider.kind = granular::BackendKind::Cuda;
  provider.unusable_reason = [] {
    std::string why;
    granular::cuda_device_available(&why);
    return why;
  };
  provider.create = granular::make_cuda_backend;
  provider.device_uuid = []() -> std::optional<std::array<std::uint8_t, 16>> {
    if (!granular::cuda_device_available()) return std::nullopt;
    return granular::cuda_device_uuid_of_current();
  };
  return provider;
}

/// Registers the provider; returns 1 so that a global's initialiser can do it.
int register_cuda_backend() {
  granular::register_backend(cuda_provider());
  return 1;
}

}  // namespace

/// 1 once the CUDA backend is registered (static initialisation): the symbol the link option of
/// granular_cuda names, so that this object, and with it the registration, is always linked.
extern "C" const int granular_cuda_backend_registered;
extern "C" const int granular_cuda_backend_registered = register_cuda_backend();
