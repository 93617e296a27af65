#include "granular/extend/backend_registry.hpp"

#include <map>
#include <mutex>

#include "granular/errors.hpp"
#include "granular/external_memory.hpp"

namespace granular {

namespace {

/// The registered providers and their lock: function-local statics, so a backend library may
/// register from its own static initialisers in any order relative to this file's.
struct Registry {
  std::mutex mutex;
  std::map<BackendKind, BackendProvider> providers;
};

Registry& registry() {
  static Registry instance;
  return instance;
}

}  // namespace

void register_backend(BackendProvider provider) {
  if (provider.kind != BackendKind::Cuda)
    throw InvalidArgument(std::string("register_backend: BackendProvider::kind = ") + backend_name(provider.kind) +
                          "; the CPU backend is built in and auto is a choice, so only cuda is registered");
  if (!provider.unusable_reason || !provider.create || !provider.device_uuid)
    throw InvalidArgument(std::string("register_backend: the ") + backend_name(provider.kind) +
                          " provider's unusable_reason, create and device_uuid must all be set");
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  r.providers.insert_or_assign(provider.kind, std::move(provider));
}

std::optional<BackendProvider> registered_backend(BackendKind kind) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  const auto found = r.providers.find(kind);
  if (found == r.providers.end()) return std::nullopt;
  return found->second;
}

std::optional<std::array<std::uint8_t, 16>> cuda_device_uuid() {
  const std::optional<BackendProvider> cuda = registered_backend(BackendKind::Cuda);
  if (!cuda) return std::nullopt;
  return cuda->device_uuid();
}

}  // namespace granular
