#pragma once
/// @file threads.hpp
/// Deprecated path, kept so existing code builds: include <granular/extend/threads.hpp>.
#include "granular/extend/threads.hpp"
