#pragma once
/// @file output_paths.hpp
/// The files and folders a command writes its results to (`accuracy --csv FILE`, `--out DIR`):
/// judged before any work, so a run of minutes never ends in a path that cannot be written, and
/// written so that every failed write (a full disk, /dev/full) is an error, never a silent loss.
/// Every message starts with the option and the value: "--csv /x/y.csv: its folder ...".

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>
#include <string_view>

namespace granular::cli {

/// A CLI11 check that refuses an empty value ("--save: needs a file or folder name, not an empty
/// value"), for every option that names a path to write or read: "" would silently name none.
CLI::Validator non_empty_path();

/// Throws FileError "<option> <path>: ..." unless `path` can be created or overwritten: it is not a
/// folder, and it is a writable existing file or its folder exists and is writable.
void check_output_file(std::string_view option, const std::filesystem::path& path);

/// Creates the folder `dir` (and its parents) when missing; throws FileError "<option> <dir>: ..."
/// when it cannot be created, is not a folder or is not writable.
void prepare_output_folder(std::string_view option, const std::filesystem::path& dir);

/// Writes `text` to `path` (replacing it); throws FileError naming the path and the system's reason
/// when opening, writing or closing fails.
void write_output_file(const std::filesystem::path& path, const std::string& text);

/// Flushes standard output; throws FileError with the system's reason when what was printed could
/// not all be written (`> /dev/full`, a closed pipe).
void flush_standard_output();

}  // namespace granular::cli
