// SPDX-License-Identifier: Apache-2.0
/// @file script_start.h
/// @brief Where replaying a stroke script starts: its start snapshot, and a Sculptor there.
///
/// Joins the script format (stroke_script.h: domain and start shape) to the engine
/// (sculptor.h), so that neither depends on the other. A start shape is generated at the
/// requested level; a start from a file (Shape::Kind::File) is loaded as it is, at its own
/// level. Owned by the caller; the edit thread.
#pragma once

#include "adf/adf.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"

#include <cstddef>
#include <memory>
#include <string>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

/// A Sculptor at the script's start (`level` 0: the script's own), its reference (what depth
/// and height limits measure from) set to that start: the shape, or a file start's clay.
/// @throw as startAdf.
std::unique_ptr<Sculptor> makeSculptor(const Script& script, int level, util::ThreadPool* pool = nullptr,
                                       std::size_t historyBytes = std::size_t(1) << 30);

/// The snapshot a script starts from, at `level` (0: the script's own level). A file start is
/// `script.start.clay` when set, else the file read (Script::baseDir joined to a relative path).
/// @throw std::invalid_argument for an invalid domain or level; for a file start, when `level`
///        is not 0 and not the file's ("a start from a file keeps its level N") or the file's
///        domain is not the header's. kizamu::FileError when the file cannot be read.
/// Complexity: a full generation (a shape) or a file read (a file start). Cold path.
adf::AdfPtr startAdf(const Script& script, int level, util::ThreadPool* pool = nullptr);

/// Where a file start is read from: `script.start.file` resolved against Script::baseDir.
std::string startFilePath(const Script& script);

}  // namespace kizamu::sculpt
