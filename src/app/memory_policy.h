// SPDX-License-Identifier: Apache-2.0
/// @file memory_policy.h
/// @brief The `kizamu` executable's process-wide memory policy: which allocator serves it and
/// how it asks the kernel for pages.
///
/// Libraries set no process-wide policy; the executable decides, once, first thing in main().
/// Why it matters: an edit's re-mesh chases pointers through megabytes of per-tile state, so it
/// is bound by TLB misses and page faults, both dear on a virtual machine (a two-level page walk
/// each). The measurements: docs/decisions/0007-mimalloc-huge-pages.md.
#pragma once

#include <string>

namespace kizamu::app {

/// Sets the policy. Built with mimalloc (KIZAMU_MIMALLOC, the default outside sanitizer
/// builds): mimalloc serves every allocation and backs its segments with transparent huge pages
/// (2 MiB, madvise), so the mesher's and the snapshots' scattered records share few TLB
/// entries and a growing session faults its memory in 2 MiB at a time. The main thread's heap
/// predates the policy (main.cpp runs commands on a thread of their own). Either way freed
/// memory is kept in the process instead of being handed back to the kernel and faulted in
/// again (under glibc a page at a time). Call before any thread starts.
void applyMemoryPolicy();

/// One line saying which allocator serves `malloc` in this process and how: checked by asking
/// the allocator about a fresh block, not taken from the build settings (`kizamu --version`).
/// With mimalloc it ends with how the kernel maps the calling thread's heap ("huge pages
/// allowed", "4 KiB pages only" or "unknown").
std::string memoryPolicySummary();

}  // namespace kizamu::app
