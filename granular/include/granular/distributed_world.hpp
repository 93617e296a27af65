#pragma once
/// @file distributed_world.hpp
/// Deprecated path, kept so existing code builds: include <granular/distributed/distributed_world.hpp>.
#include "granular/distributed/distributed_world.hpp"
