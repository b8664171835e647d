// SPDX-License-Identifier: Apache-2.0
/// @file lattice.h
/// @brief Lattice points packed into one 64-bit key: the one packing every module uses.
///
/// A lattice point is an integer corner coordinate at the finest level (0..2^L per axis,
/// L <= 16), so each axis fits in 20 bits and a key is x | y << 20 | z << 40. Keys of points
/// compare equal exactly when the points do, and sums and differences of keys are the keys of
/// sums and differences of points as long as no field leaves 0..2^20 - 1 (the mesher steps
/// along edges that way).
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>

namespace kizamu::adf {

/// Bits per axis in a packed lattice key.
constexpr int kLatticeKeyBits = 20;
/// The mask of one axis's field.
constexpr uint64_t kLatticeKeyMask = (uint64_t(1) << kLatticeKeyBits) - 1;

/// `p` packed: x | y << 20 | z << 40. Precondition: every coordinate below 2^20.
constexpr uint64_t packLattice(glm::uvec3 p) {
    return uint64_t(p.x) | (uint64_t(p.y) << kLatticeKeyBits) | (uint64_t(p.z) << (2 * kLatticeKeyBits));
}

/// The point packed in `key` (the inverse of packLattice).
constexpr glm::uvec3 unpackLattice(uint64_t key) {
    return {uint32_t(key & kLatticeKeyMask), uint32_t((key >> kLatticeKeyBits) & kLatticeKeyMask),
            uint32_t((key >> (2 * kLatticeKeyBits)) & kLatticeKeyMask)};
}

}  // namespace kizamu::adf
