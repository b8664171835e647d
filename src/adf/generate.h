// SPDX-License-Identifier: Apache-2.0
/// @file generate.h
/// @brief Tiled ADF generation (Kizamu 5.1, 5.2) and local regeneration, the edit primitive.
///
/// Top-down subdivision against an error criterion evaluated at the 19 cell, face and edge
/// centres (with the 8 corners, the 27 children's corners), with Bremer's adaptive bound inside a
/// band around the surface (bounded-surface generation). Every lattice point is evaluated at
/// most once per run: points above the tile level are cached in a table, points inside a tile
/// in the tile's scratch volume, and points on a shared tile face or edge are handed from the
/// tile that computed them to its neighbours. Tiles are generated in 8 colours (slot parity),
/// each tile after its neighbours of lower colours (no two tiles that share a face, edge or
/// corner run at once); that keeps the hand-over race free and the evaluation count the same
/// in serial and parallel runs. The exception: a run of fewer than 8 tiles per thread (a dab,
/// a LOD) runs every tile at once, the large ones in parts, and evaluates the points tiles and
/// parts share once each: the same bytes, but a count that depends on the thread count.
#pragma once

#include "adf/adf.h"
#include "adf/distance_source.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>

namespace kizamu::util {
class ThreadPool;
}

namespace kizamu::adf {

/// Counters of one generation or regeneration run.
struct GenerationStats {
    uint64_t samples = 0;         ///< distance-function evaluations
    uint64_t tilesGenerated = 0;  ///< tiles (tile level) built by this run
    uint64_t coarseTiles = 0;     ///< single-cell tiles above the tile level built by this run
    uint64_t cells = 0;           ///< leaf cells in the tiles built by this run
};

/// How far a generation has come, for a reporter on another thread (a progress line). The run
/// only adds to the counters (relaxed atomics: a worker never waits for the reader); read them
/// at any time. Tiles are the unit because they are what the pool runs; the upper pass before
/// them is short.
struct GenerationProgress {
    std::atomic<uint64_t> tilesTotal{0};  ///< tiles the run will build: 0 until the upper pass ends
    std::atomic<uint64_t> tilesDone{0};   ///< tiles built so far (tilesTotal at the end)
};

/// Generates the ADF of `source` over `domain`.
/// @param pool      worker threads, or null for a serial run (same bytes either way)
/// @param stats     optional counters
/// @param progress  optional: counts tiles as they finish (see GenerationProgress)
/// Complexity: O(cells near the surface and band) evaluations, each distance evaluated once
/// (shared border points once per tile or part in a run of fewer than 8 tiles per thread).
/// Threading: parallel over tiles on `pool`; `source` must be thread-safe. Memory: the ADF plus
/// one scratch volume of (2^span+1)^3 floats per worker and the shared tile faces.
/// @throw std::invalid_argument for an invalid domain or settings; std::domain_error when the
///        source returns a NaN or infinite distance (nothing is published then).
AdfPtr generate(const DistanceSource& source, const Domain& domain,
                const GenerationSettings& settings, util::ThreadPool* pool = nullptr,
                GenerationStats* stats = nullptr, GenerationProgress* progress = nullptr);

/// Regenerates every tile of `base` that overlaps `regionWorld` from `source`, and the cells
/// above them, sharing everything else with `base`. Inside a rebuilt tile, cells wholly outside
/// the region are copied from `base`'s tile where it has them (sub-tile regeneration): `source`
/// must equal `base`'s field outside the region. The result equals (bit for bit) a full
/// generation of `source` provided `source` equals the field `base` was generated from outside
/// the region and the tiles' quantisation scales do not change (tested with a tool edit; a
/// rebuilt tile keeps its old scale whenever its new values fit it).
/// The new snapshot's version is base.version() + 1.
/// Complexity: O(cells overlapping the region) evaluations, O(cells of the touched tiles)
/// copying, plus O(root + touched chunks).
/// Threading: as generate(). Memory: the new tiles and copied chunks.
AdfPtr regenerate(const Adf& base, const DistanceSource& source, const BoxWorld& regionWorld,
                  util::ThreadPool* pool = nullptr, GenerationStats* stats = nullptr);

}  // namespace kizamu::adf
