#pragma once
/// @file backend_registry.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/backend_registry.hpp>.
#include "granular/extend/backend_registry.hpp"
