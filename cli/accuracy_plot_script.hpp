#pragma once
/// @file accuracy_plot_script.hpp
/// Where `granular accuracy --out` finds plot_accuracy.py, the script that draws its plots.

#include <filesystem>

namespace granular::cli {

/// The plot script for the program at `program`: the installed copy beside it (<prefix>/bin/granular
/// uses <prefix>/share/granular/plot_accuracy.py, wherever the prefix was moved); for the program in
/// its build tree, which has no installed copy, the source tree's accuracy/plot_accuracy.py. When
/// neither exists, the installed location, so a message can name where the script belongs. An empty
/// `program` (its path unknown) gives the copy under the configured install prefix.
std::filesystem::path accuracy_plot_script(const std::filesystem::path& program);

/// accuracy_plot_script() for the running program (/proc/self/exe).
std::filesystem::path accuracy_plot_script();

}  // namespace granular::cli
