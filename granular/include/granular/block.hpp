#pragma once
/// @file block.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/block.hpp>.
#include "granular/extend/block.hpp"
