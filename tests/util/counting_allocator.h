// SPDX-License-Identifier: Apache-2.0
/// @file counting_allocator.h
/// @brief Per-thread counts of global operator new/delete calls (the test binary that links
/// counting_allocator.cpp replaces the global allocation functions).
#pragma once

#include <cstdint>

namespace kizamu::test {

struct AllocationCounts {
    uint64_t allocations = 0;
    uint64_t frees = 0;
};

/// Counts for the calling thread since it started.
AllocationCounts threadAllocationCounts();

}  // namespace kizamu::test
