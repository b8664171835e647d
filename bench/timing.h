// SPDX-License-Identifier: Apache-2.0
/// @file timing.h
/// @brief Timing helpers: wall-clock seconds, medians, percentiles, batched per-query latency.
///
/// Per-query latencies of a few nanoseconds cannot be timed one by one (a clock read costs
/// ~20 ns), so queries run in batches of kQueryBatch consecutive points; each batch's time
/// divided by its size is one latency sample, and percentiles are taken over those samples.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

namespace kizamu::bench {

inline constexpr std::size_t kQueryBatch = 16;

inline double nowSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The q-quantile (0..1) of `v` (copied, nearest rank).
inline double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}
inline double median(std::vector<double> v) { return quantile(std::move(v), 0.5); }

/// Per-query nanoseconds of `query(i)` for i in [0, n), batched; `query` returns a float that
/// is summed into `sink` so the compiler cannot drop the work.
template <class Query>
std::vector<double> batchedLatenciesNs(std::size_t n, Query&& query, float& sink) {
    std::vector<double> out;
    out.reserve(n / kQueryBatch + 1);
    float acc = 0.0f;
    for (std::size_t b = 0; b + kQueryBatch <= n; b += kQueryBatch) {
        const auto t0 = std::chrono::steady_clock::now();
        for (std::size_t i = b; i < b + kQueryBatch; ++i) acc += query(i);
        const auto t1 = std::chrono::steady_clock::now();
        out.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(kQueryBatch));
    }
    sink += acc;
    return out;
}

}  // namespace kizamu::bench
