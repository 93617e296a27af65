#pragma once
/// @file tools.hpp
/// Deprecated path, kept so existing code builds: include <granular/change_report.hpp>.
#include "granular/change_report.hpp"
