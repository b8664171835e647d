// SPDX-License-Identifier: Apache-2.0
/// @file adf_compare.h
/// @brief Test helpers: byte-wise comparison of two snapshots, a counting source.
#pragma once

#include "adf/adf.h"
#include "adf/colour_layer.h"
#include "adf/distance_source.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <set>
#include <tuple>

namespace kizamu::test {

/// Both unpainted, or the same painted slots with the same points and colours.
inline ::testing::AssertionResult sameColours(const adf::Adf& a, const adf::Adf& b) {
    const adf::ColourLayer* ca = a.colours().get();
    const adf::ColourLayer* cb = b.colours().get();
    if (!ca || !cb) return ca == cb ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << "only one is painted";
    if (ca->baseColour() != cb->baseColour()) return ::testing::AssertionFailure() << "base colours differ";
    if (!std::equal(ca->slotKeys().begin(), ca->slotKeys().end(), cb->slotKeys().begin(), cb->slotKeys().end()))
        return ::testing::AssertionFailure() << "painted slots differ";
    for (std::size_t i = 0; i < ca->slotCount(); ++i) {
        const adf::ColourTile& ta = *ca->tiles()[i];
        const adf::ColourTile& tb = *cb->tiles()[i];
        if (!std::equal(ta.points().begin(), ta.points().end(), tb.points().begin(), tb.points().end()) ||
            !std::equal(ta.colours().begin(), ta.colours().end(), tb.colours().begin(), tb.colours().end()))
            return ::testing::AssertionFailure() << "paint differs in slot " << ca->slotKeys()[i];
    }
    return ::testing::AssertionSuccess();
}

/// Every slot maps to tiles with identical level, origin, scale, nodes and corners, and the
/// paint is the same. `scaleMayDiffer`: tiles may be quantised at different scales (a rebuilt
/// tile keeps its old one when its values fit), and then their values agree within half a
/// step of each; tiles at the same scale must still match bit for bit.
inline ::testing::AssertionResult sameAdf(const adf::Adf& a, const adf::Adf& b, bool scaleMayDiffer = false) {
    if (!(a.domain() == b.domain())) return ::testing::AssertionFailure() << "domains differ";
    if (auto paint = sameColours(a, b); !paint) return paint;
    const uint32_t n = a.domain().slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const adf::Tile* ta = a.tileAtSlot({x, y, z});
                const adf::Tile* tb = b.tileAtSlot({x, y, z});
                auto fail = [&](const char* what) {
                    return ::testing::AssertionFailure() << what << " differs at slot " << x << "," << y << "," << z;
                };
                if (ta->level() != tb->level()) return fail("tile level");
                if (ta->latticeOrigin() != tb->latticeOrigin()) return fail("tile origin");
                if (ta->nodeCount() != tb->nodeCount() || ta->leafCount() != tb->leafCount() ||
                    ta->brickCount() != tb->brickCount())
                    return fail("cell count");
                if (std::memcmp(ta->nodes(), tb->nodes(), ta->nodeCount() * 4) != 0) return fail("node words");
                if (ta->scale() != tb->scale()) {
                    if (!scaleMayDiffer) return fail("quantisation scale");
                    const double tolerance = 0.5 * (double(ta->scale()) + double(tb->scale())) * (1.0 + 1e-6);
                    auto near = [&](const int16_t* qa, const int16_t* qb, std::size_t count) {
                        for (std::size_t i = 0; i < count; ++i)
                            if (std::abs(double(qa[i]) * ta->scale() - double(qb[i]) * tb->scale()) > tolerance) return false;
                        return true;
                    };
                    if (!near(ta->corners(), tb->corners(), ta->leafCount() * 8) ||
                        !near(ta->bricks(), tb->bricks(), ta->brickCount() * 27))
                        return fail("corner distances (beyond quantisation)");
                    continue;
                }
                if (std::memcmp(ta->corners(), tb->corners(), ta->leafCount() * 16) != 0 ||
                    std::memcmp(ta->bricks(), tb->bricks(), ta->brickCount() * 54) != 0)
                    return fail("corner distances");
            }
    return ::testing::AssertionSuccess();
}

/// Wraps a source and records every point it is asked for (thread-safe, slow: tests only).
class CountingSource final : public adf::DistanceSource {
public:
    explicit CountingSource(adf::SourcePtr inner) : mInner(std::move(inner)) {}
    double distance(const glm::dvec3& p) const override {
        record(p);
        return mInner->distance(p);
    }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        for (const auto& q : p) record(q);
        mInner->distances(p, out);
    }
    std::size_t evaluations() const { return mEvaluations; }
    std::size_t distinctPoints() const { return mPoints.size(); }

private:
    void record(const glm::dvec3& p) const {
        std::lock_guard lock(mMutex);
        ++mEvaluations;
        mPoints.emplace(p.x, p.y, p.z);
    }
    adf::SourcePtr mInner;
    mutable std::mutex mMutex;
    mutable std::size_t mEvaluations = 0;
    mutable std::set<std::tuple<double, double, double>> mPoints;
};

}  // namespace kizamu::test
