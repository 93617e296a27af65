#pragma once
/// @file backend.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/backend.hpp>.
#include "granular/extend/backend.hpp"
