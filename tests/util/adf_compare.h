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
#include <utility>
#include <vector>

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

/// The same tree, and decoded values within the rounding of both tiles (half a quantisation
/// step each, and half a leaf step each where they are packed in leaf steps, a leaf step where
/// in far steps) and a leaf step more for a copy's older rounding.
inline bool sameUpToQuantisation(const adf::Tile& a, const adf::Tile& b) {
    auto rounding = [](const adf::Tile& t, bool packed, bool far) {
        return 0.5 * double(t.scale()) * (far ? 2.0 * double(t.leafStep()) + 1.0 : packed ? double(t.leafStep()) + 1.0 : 1.0);
    };
    auto brickTolerance = [&](const adf::Tile& t, uint32_t brick) {
        return rounding(t, brick < t.packedBrickCount(), brick >= t.packedBrickCount() - t.farBrickCount() && brick < t.packedBrickCount());
    };
    auto leafTolerance = [&](const adf::Tile& t, uint32_t leaf) {
        const uint32_t group = leaf >> 3;
        const bool far = leaf < 8 * t.groupCount() && group < t.packedGroupCount() && group >= t.packedGroupCount() - t.farGroupCount();
        return rounding(t, t.packedLeaf(leaf), far);
    };
    // A copied cell may carry the rounding of the tile it was copied from too: a packed item's,
    // within a leaf step (a far group's 4-cell leaf, say, copied where it is stored wide). The
    // other tile may store it wide as well (its group, straddling the edit, went wide there),
    // so wide items get the slack too.
    const double copiedSlack = std::max(double(a.leafStep()) * double(a.scale()), double(b.leafStep()) * double(b.scale()));
    std::vector<std::pair<uint32_t, uint32_t>> stack{{a.node(0), b.node(0)}};
    while (!stack.empty()) {
        const auto [wa, wb] = stack.back();
        stack.pop_back();
        if (adf::node::isInternal(wa) != adf::node::isInternal(wb) || adf::node::isBrick(wa) != adf::node::isBrick(wb) ||
            adf::node::isLeaf(wa) != adf::node::isLeaf(wb))
            return false;
        if (adf::node::isInternal(wa)) {
            for (uint32_t c = 0; c < 8; ++c) stack.emplace_back(a.node(wa + c), b.node(wb + c));
        } else if (adf::node::isBrick(wa)) {
            const uint32_t ka = adf::node::brickIndex(wa), kb = adf::node::brickIndex(wb);
            const double tolerance = (brickTolerance(a, ka) + brickTolerance(b, kb) + copiedSlack) * (1.0 + 1e-6);
            for (int g = 0; g < 27; ++g)
                if (std::abs(double(a.brickValue(ka, g)) * a.scale() - double(b.brickValue(kb, g)) * b.scale()) > tolerance)
                    return false;
        } else {
            if (adf::node::leafType(wa) != adf::node::leafType(wb)) return false;
            const uint32_t la = adf::node::leafIndex(wa), lb = adf::node::leafIndex(wb);
            const double tolerance = (leafTolerance(a, la) + leafTolerance(b, lb) + copiedSlack) * (1.0 + 1e-6);
            for (int c = 0; c < 8; ++c)
                if (std::abs(double(a.corner(la, c)) - double(b.corner(lb, c))) > tolerance)
                    return false;
        }
    }
    return true;
}

/// The first slot where `differs(tile of a, tile of b)` names a difference, as a failure ("X
/// differs at slot x,y,z"); success when there is none. Domains must match.
template <class Differs>
::testing::AssertionResult firstSlotWhere(const adf::Adf& a, const adf::Adf& b, const Differs& differs) {
    if (!(a.domain() == b.domain())) return ::testing::AssertionFailure() << "domains differ";
    const uint32_t n = a.domain().slotsPerAxis();
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x)
                if (const char* what = differs(*a.tileAtSlot({x, y, z}), *b.tileAtSlot({x, y, z})))
                    return ::testing::AssertionFailure() << what << " differs at slot " << x << "," << y << "," << z;
    return ::testing::AssertionSuccess();
}

/// What sameAdf finds different between two tiles, or null.
inline const char* tileDifference(const adf::Tile& ta, const adf::Tile& tb, bool scaleMayDiffer) {
    if (ta.level() != tb.level()) return "tile level";
    if (ta.latticeOrigin() != tb.latticeOrigin()) return "tile origin";
    if (ta.nodeCount() != tb.nodeCount() || ta.leafCount() != tb.leafCount() || ta.brickCount() != tb.brickCount())
        return "cell count";
    if (ta.scale() != tb.scale()) {
        if (!scaleMayDiffer) return "quantisation scale";
        return sameUpToQuantisation(ta, tb) ? nullptr : "tree or distances (beyond quantisation)";
    }
    if (ta.nodeWords() != tb.nodeWords()) return "node words";
    if (ta.narrowBrickCount() != tb.narrowBrickCount() || ta.coarseBrickCount() != tb.coarseBrickCount() ||
        ta.farBrickCount() != tb.farBrickCount() || ta.leafStep() != tb.leafStep())
        return "brick encoding";
    if (ta.narrowLeafCount() != tb.narrowLeafCount() || ta.groupCount() != tb.groupCount() ||
        ta.narrowGroupCount() != tb.narrowGroupCount() || ta.packedGroupCount() != tb.packedGroupCount() ||
        ta.farGroupCount() != tb.farGroupCount() || ta.groupedLeafCount() != tb.groupedLeafCount())
        return "leaf encoding";
    for (uint32_t k = 0; k < ta.leafCount(); ++k)
        for (int c = 0; c < 8; ++c)
            if (ta.leafValue(k, c) != tb.leafValue(k, c)) return "corner distances";
    for (uint32_t k = 0; k < ta.brickCount(); ++k)
        for (int g = 0; g < 27; ++g)
            if (ta.brickValue(k, g) != tb.brickValue(k, g)) return "brick distances";
    if (ta.checksum() != tb.checksum()) return "tile checksum";
    return nullptr;
}

/// Every slot maps to tiles with identical level, origin, scale, nodes and corners, and the
/// paint is the same. `scaleMayDiffer`: tiles may be quantised at different scales (a rebuilt
/// tile keeps its old one when its values fit), and then their values agree within half a
/// step of each; tiles at the same scale must still match bit for bit.
inline ::testing::AssertionResult sameAdf(const adf::Adf& a, const adf::Adf& b, bool scaleMayDiffer = false) {
    if (!(a.domain() == b.domain())) return ::testing::AssertionFailure() << "domains differ";
    if (auto paint = sameColours(a, b); !paint) return paint;
    return firstSlotWhere(a, b, [scaleMayDiffer](const adf::Tile& ta, const adf::Tile& tb) {
        return tileDifference(ta, tb, scaleMayDiffer);
    });
}

/// The same tiles, trees and cells, and values within both tiles' rounding, whatever the storage
/// (packing, leaf groups, scale): what an edit must give against a fresh generation.
inline ::testing::AssertionResult sameFieldUpToQuantisation(const adf::Adf& a, const adf::Adf& b) {
    return firstSlotWhere(a, b, [](const adf::Tile& ta, const adf::Tile& tb) -> const char* {
        if (ta.level() != tb.level() || ta.latticeOrigin() != tb.latticeOrigin() || ta.nodeCount() != tb.nodeCount() ||
            ta.cellCount() != tb.cellCount())
            return "the tree";
        if (!sameUpToQuantisation(ta, tb)) return "the field (tree or distances beyond quantisation)";
        return nullptr;
    });
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
