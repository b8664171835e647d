// SPDX-License-Identifier: Apache-2.0
/// @file adf_file.h
/// @brief The .kza file: a versioned, checksummed binary image of one ADF snapshot.
///
/// Layout (little-endian, docs/FILE-FORMATS.md): a fixed header (magic, format version, domain,
/// generation settings, snapshot version, tile count), one record per distinct tile (level,
/// lattice origin, scale, node words, 16-bit corners), then (version 2) tagged sections, each
/// with its own length: so far the optional colour layer ('COLR'); then a CRC-32 of everything
/// before it. Version-1 files (no sections) still load.
/// Loading validates every field and the tree structure, so a truncated, corrupt or foreign
/// file gives a one-line FileError and never a crash. Cold path; any thread.
#pragma once

#include "adf/adf.h"

#include <cstddef>
#include <string>
#include <vector>

namespace kizamu::adf {

/// Written by this build; it reads versions 1 and 2.
inline constexpr uint32_t kAdfFormatVersion = 2;

/// Serialises `adf`. Complexity: O(size). Memory: the returned buffer.
std::vector<std::byte> encodeAdf(const Adf& adf);
/// Parses and validates `bytes`; `name` prefixes error messages.
/// @throw kizamu::FileError naming the problem.
AdfPtr decodeAdf(const std::string& bytes, const std::string& name);

/// Writes `adf` to `path` atomically (temporary file, fsync, rename). @throw kizamu::FileError
void saveAdf(const Adf& adf, const std::string& path);
/// Reads and validates `path`. @throw kizamu::FileError
AdfPtr loadAdf(const std::string& path);

}  // namespace kizamu::adf
