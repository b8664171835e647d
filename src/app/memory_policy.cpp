// SPDX-License-Identifier: Apache-2.0
/// @file memory_policy.cpp
/// @brief applyMemoryPolicy: mimalloc with huge pages, or glibc keeping its freed memory.
#include "app/memory_policy.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#if KIZAMU_MIMALLOC
#include <mimalloc.h>
#elif defined(__GLIBC__)
#include <malloc.h>
#endif

// Sanitizers replace malloc with their own (GCC defines these; clang answers __has_feature).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define KIZAMU_SANITIZER_MALLOC 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define KIZAMU_SANITIZER_MALLOC 1
#endif
#endif

namespace kizamu::app {

namespace {
bool gFreedMemoryKept = false;  ///< what the allocator said when the policy was set
}  // namespace

void applyMemoryPolicy() {
#if KIZAMU_MIMALLOC
    // Segments mapped from now on are advised as huge pages (the few made during static
    // initialisation keep 4 KiB pages). Where transparent huge pages are off, nothing changes.
    mi_option_enable(mi_option_large_os_pages);
    // A thread's first segment too: by default it is committed a piece at a time (for short
    // threads), and pieces cannot be huge pages, so the edit's and the pool's first 32 MiB would
    // be touched 4 KiB at a time, a page fault each (docs/decisions/0007-mimalloc-huge-pages.md).
    mi_option_set(mi_option_eager_commit_delay, 0);
    // And freed memory stays committed, as under glibc below: handed back after mimalloc's
    // delay, a freed 2 MiB page would come back zeroed and be faulted in again by the next
    // frame's buffers (docs/decisions/0007-mimalloc-huge-pages.md).
#if MI_MALLOC_VERSION >= 210
    mi_option_set(mi_option_purge_delay, -1);  // 2.1 renamed decommitting "purging"; -1: never
    gFreedMemoryKept = mi_option_get(mi_option_purge_delay) < 0;
#else
    mi_option_disable(mi_option_allow_decommit);
    gFreedMemoryKept = !mi_option_is_enabled(mi_option_allow_decommit);
#endif
#elif defined(__GLIBC__) && !defined(KIZAMU_SANITIZER_MALLOC)
    // Meshing, points and edits free and allocate buffers of megabytes every frame; by default
    // glibc hands large ones back to the kernel (fresh mmap above its threshold, heap trimming),
    // so the next frame takes a page fault per 4 KiB again
    // (docs/decisions/0007-mimalloc-huge-pages.md). Blocks above 32 MiB (the ceiling of glibc's
    // own adaptive threshold) are still mapped, and more than 256 MiB free at an arena's top is
    // still returned. A value glibc refuses leaves its default (and the summary says so).
    gFreedMemoryKept = mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1;
    gFreedMemoryKept = mallopt(M_TRIM_THRESHOLD, 256 << 20) == 1 && gFreedMemoryKept;
#endif
}

#if KIZAMU_MIMALLOC
namespace {
/// Whether the kernel may back the mapping holding `p` with huge pages (/proc/self/smaps,
/// THPeligible), or "unknown" where it does not say (no /proc, kernels before 5.0).
std::string pagesAt(const void* p) {
    const auto at = reinterpret_cast<uintptr_t>(p);
    const std::unique_ptr<FILE, decltype(&std::fclose)> f(std::fopen("/proc/self/smaps", "r"),
                                                          &std::fclose);
    if (!f) return "unknown";
    char line[512];
    bool inside = false, lineStart = true;  // a long path comes in pieces: read line starts only
    while (std::fgets(line, sizeof line, f.get())) {
        const bool start = lineStart;
        lineStart = std::strchr(line, '\n') != nullptr;
        if (!start) continue;
        unsigned long lo = 0, hi = 0;
        char perms[8];
        if (std::sscanf(line, "%lx-%lx %7s", &lo, &hi, perms) == 3) {
            inside = lo <= at && at < hi;
            continue;
        }
        int eligible = 0;
        if (inside && std::sscanf(line, "THPeligible: %d", &eligible) == 1)
            return eligible ? "huge pages allowed" : "4 KiB pages only";
    }
    return "unknown";
}
}  // namespace
#endif

std::string memoryPolicySummary() {
    [[maybe_unused]] const char* freed = gFreedMemoryKept ? "freed memory kept" : "freed memory returned";
#if KIZAMU_MIMALLOC
    const std::unique_ptr<void, decltype(&std::free)> probe(std::malloc(64), &std::free);
    const int v = mi_version();  // 209: 2.0.9
    std::string s = "memory: mimalloc " + std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." + std::to_string(v % 10);
    s += mi_is_in_heap_region(probe.get()) ? " serves malloc" : " linked but NOT serving malloc";
    const bool huge = mi_option_is_enabled(mi_option_large_os_pages) && mi_option_get(mi_option_eager_commit_delay) == 0;
    s += huge ? ", huge pages advised, " : ", 4 KiB pages, ";
    // The heap of the thread asking (a command's, main.cpp), as the kernel maps it.
    return s + freed + "; this thread's heap: " + pagesAt(probe.get());
#elif defined(KIZAMU_SANITIZER_MALLOC)
    return "memory: the sanitizer's malloc (no policy set)";
#elif defined(__GLIBC__)
    return std::string("memory: glibc malloc, ") + freed + " (mmap threshold 32 MiB, trim threshold 256 MiB)";
#else
    return "memory: the C library's malloc (no policy set)";
#endif
}

}  // namespace kizamu::app
