#pragma once
/// @file slab_layout.hpp
/// Deprecated path, kept so existing code builds: include <granular/distributed/slab_layout.hpp>.
#include "granular/distributed/slab_layout.hpp"
