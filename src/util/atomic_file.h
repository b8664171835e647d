// SPDX-License-Identifier: Apache-2.0
/// @file atomic_file.h
/// @brief Replace a file so that a crash at any moment leaves either the old or the new one.
///
/// Writes `path.tmp`, fsyncs it, renames it over `path` and fsyncs the directory. Cold path.
#pragma once

#include <cstddef>
#include <span>
#include <string>

namespace kizamu::util {

/// Writes `bytes` to `path` atomically. @throw kizamu::FileError naming the failing step.
void writeFileAtomically(const std::string& path, std::span<const std::byte> bytes);

/// Makes a directory's entries (a created or renamed file) durable; best effort.
void fsyncDirectory(const std::string& dir);

/// Reads the whole file. @throw kizamu::FileError when it cannot be opened or read.
std::string readWholeFile(const std::string& path);

}  // namespace kizamu::util
