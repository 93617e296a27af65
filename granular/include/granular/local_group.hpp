#pragma once
/// @file local_group.hpp
/// Deprecated path, kept so existing code builds: include <granular/distributed/local_group.hpp>.
#include "granular/distributed/local_group.hpp"
