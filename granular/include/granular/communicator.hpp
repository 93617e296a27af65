#pragma once
/// @file communicator.hpp
/// Deprecated path, kept so existing code builds: include <granular/distributed/communicator.hpp>.
#include "granular/distributed/communicator.hpp"
