#pragma once
/// @file lut.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/lut.hpp>.
#include "granular/extend/lut.hpp"
