#pragma once
/// @file memory_budget.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/memory_budget.hpp>.
#include "granular/extend/memory_budget.hpp"
