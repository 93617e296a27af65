#pragma once
/// @file activity.hpp
/// Deprecated path, kept so existing code builds: include <granular/bricks.hpp>.
#include "granular/bricks.hpp"
