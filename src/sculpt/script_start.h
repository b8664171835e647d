// SPDX-License-Identifier: Apache-2.0
/// @file script_start.h
/// @brief Where replaying a stroke script starts: its start snapshot, and a Sculptor there.
///
/// Joins the script format (stroke_script.h: domain and start shape) to the engine
/// (sculptor.h), so that neither depends on the other. Owned by the caller; the edit thread.
#pragma once

#include "adf/adf.h"
#include "sculpt/sculptor.h"
#include "sculpt/stroke_script.h"

#include <cstddef>
#include <memory>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::sculpt {

/// A Sculptor at the script's start shape (`level` 0: the script's own), its reference set to
/// that shape.
std::unique_ptr<Sculptor> makeSculptor(const Script& script, int level, util::ThreadPool* pool = nullptr,
                                       std::size_t historyBytes = std::size_t(1) << 30);

/// The snapshot a script starts from, at `level` (0: the script's own level).
adf::AdfPtr startAdf(const Script& script, int level, util::ThreadPool* pool = nullptr);

}  // namespace kizamu::sculpt
