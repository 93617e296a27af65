#pragma once
/// @file backend_factory.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/backend_factory.hpp>.
#include "granular/extend/backend_factory.hpp"
