/// @file cli_test_main.cpp
/// The doctest runner of the CLI's unit tests (granular_cli_tests).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
