#pragma once
/// @file fuzz_readers.hpp
/// The fuzz target of the three readers: scene JSON (parse_scene, load_scene), raw grids
/// (decode_raw, load_raw) and MagicaVoxel files (decode_vox, load_vox). Each input is fed to all
/// of them, in memory and through a file. A reader may only throw granular::Error subclasses:
/// anything else escapes LLVMFuzzerTestOneInput (libFuzzer reports it as a crash; the driver
/// catches and records it).

#include <cstddef>
#include <cstdint>
#include <string>

/// What the last input did in each reader, "<reader>: ok" or "<reader>: <message without digits>",
/// joined; the driver keeps inputs whose outcome it has not seen before.
const std::string& fuzz_last_outcome();

/// Feeds `data` to every reader. Returns 0 (libFuzzer's convention).
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
