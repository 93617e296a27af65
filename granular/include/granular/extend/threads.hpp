#pragma once
/// @file extend/threads.hpp
/// How many CPU threads granular may start: every thread count a user gives (WorldDef::threads, a
/// table build, the CLI's --threads) is checked here, so an absurd request is an error, not a
/// machine starved of threads.

namespace granular {

/// Hardware threads of this machine (at least 1).
int hardware_threads();

/// The most threads one pool may have: 4 times the hardware threads.
int max_threads();

/// The thread count a request of `threads` stands for: `threads` itself, or all hardware threads
/// for 0. Throws InvalidArgument naming `field` and the value when it is negative or above
/// max_threads().
int resolve_threads(int threads, const char* field);

}  // namespace granular
