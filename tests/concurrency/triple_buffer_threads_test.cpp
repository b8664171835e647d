// SPDX-License-Identifier: Apache-2.0
// util::TripleBuffer across threads (and under ThreadSanitizer): a writer publishing values whose
// parts must agree, a reader that never sees a torn value nor one older than it already saw.
#include "util/triple_buffer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>

namespace kizamu {
namespace {

struct Pair {
    uint64_t a = 0, b = 0;  ///< always b == 3 a + 1 in a whole value
    uint64_t padding[6] = {};
};

TEST(TripleBufferThreads, TheReaderSeesWholeValuesInOrder) {
    util::TripleBuffer<Pair> buffer(Pair{0, 1, {}});
    std::atomic<bool> done{false};
    constexpr uint64_t kWrites = 200'000;
    std::thread writer([&] {
        for (uint64_t i = 1; i <= kWrites; ++i) buffer.write(Pair{i, 3 * i + 1, {}});
        done.store(true, std::memory_order_release);
    });
    uint64_t last = 0, takes = 0, torn = 0, backwards = 0;
    while (true) {
        const bool finished = done.load(std::memory_order_acquire);
        if (buffer.take()) {
            ++takes;
            const Pair& p = buffer.read();
            torn += p.b == 3 * p.a + 1 ? 0 : 1;
            backwards += p.a < last ? 1 : 0;
            last = p.a;
        }
        if (finished && !buffer.take()) break;
    }
    writer.join();
    if (buffer.take()) last = buffer.read().a;
    EXPECT_EQ(torn, 0u);
    EXPECT_EQ(backwards, 0u);
    EXPECT_EQ(last, kWrites) << "the last value written is the last one read";
    EXPECT_GT(takes, 0u);
}

}  // namespace
}  // namespace kizamu
