#pragma once
/// @file hex.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/hex.hpp>.
#include "granular/extend/hex.hpp"
