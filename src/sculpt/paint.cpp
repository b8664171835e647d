// SPDX-License-Identifier: Apache-2.0
/// @file paint.cpp
/// @brief paintStroke: colour tiles rewritten where a swept tool meets the surface.
#include "sculpt/paint.h"

#include "sculpt/swept_tool.h"
#include "sculpt/symmetry.h"
#include "util/thread_pool.h"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace kizamu::sculpt {

namespace {

/// One channel of lerp(old, paint, a), rounded to the nearest byte.
uint8_t mixChannel(uint8_t old, uint8_t paint, double a) {
    const double v = double(old) + (double(paint) - double(old)) * a;
    return uint8_t(std::clamp(std::floor(v + 0.5), 0.0, 255.0));
}

/// lerp(old, paint, a) per channel, rounded to the nearest byte.
adf::Rgb8 mixColour(adf::Rgb8 old, adf::Rgb8 paint, double a) {
    return {mixChannel(old.r, paint.r, a), mixChannel(old.g, paint.g, a), mixChannel(old.b, paint.b, a)};
}

/// The lattice points of `bounds` (m), clipped to the domain, as the inclusive box [pMin, pMax];
/// false when none is left.
bool latticeBox(const adf::Domain& d, const adf::BoxWorld& bounds, glm::uvec3& pMin, glm::uvec3& pMax) {
    const double h = d.finestCellSize();
    const double last = double(d.latticeSize() - 1);
    const glm::dvec3 lo = glm::ceil((bounds.min - d.originWorld) / h), hi = glm::floor((bounds.max - d.originWorld) / h);
    if (glm::any(glm::greaterThan(lo, hi)) || glm::any(glm::lessThan(hi, glm::dvec3(0.0))) || glm::any(glm::greaterThan(lo, glm::dvec3(last))))
        return false;
    pMin = glm::uvec3(glm::clamp(lo, glm::dvec3(0.0), glm::dvec3(last)));
    pMax = glm::uvec3(glm::clamp(hi, glm::dvec3(0.0), glm::dvec3(last)));
    return true;
}

/// Calls fn(point, local index) for every lattice point of [a, b) (inside tile slot `slot`)
/// whose field value lies within `band` (m) of the surface. Leaf by leaf: a trilinear cell lies
/// between its corners' values, so a leaf whose corners are all beyond the band on one side
/// holds no band point (most of the box). Each lattice point belongs to the one leaf whose
/// half-open box holds it, as in Adf::findLeaf, so its field value is the one a lookup gives;
/// leaves come depth first, every point once.
template <class Fn>
void forEachBandPoint(const adf::Adf& adf, glm::uvec3 slot, glm::uvec3 a, glm::uvec3 b, float band, Fn&& fn) {
    const adf::Domain& d = adf.domain();
    const uint32_t span = uint32_t(d.tileSpan());
    const glm::uvec3 s0 = slot << span;
    adf::forEachLeaf(*adf.tileAtSlot(slot), d.maxLevel, [&](const adf::LeafRef& leaf) {
        bool above = true, below = true;
        for (float c : leaf.corners) {
            above = above && c > band;
            below = below && c < -band;
        }
        if (above || below) return;
        const glm::uvec3 la = glm::max(a, leaf.latticeOrigin), lb = glm::min(b, leaf.latticeOrigin + leaf.latticeSize);
        const float inv = 1.0f / float(leaf.latticeSize);
        for (uint32_t z = la.z; z < lb.z; ++z)
            for (uint32_t y = la.y; y < lb.y; ++y)
                for (uint32_t x = la.x; x < lb.x; ++x) {
                    const glm::vec3 f = (glm::vec3(float(x), float(y), float(z)) - glm::vec3(leaf.latticeOrigin)) * inv;
                    if (!(std::abs(adf::trilinear(leaf.corners, f).distance) <= band)) continue;
                    fn(glm::uvec3(x, y, z), ((z - s0.z) << (2 * span)) | ((y - s0.y) << span) | (x - s0.x));
                }
    });
}

/// `old` (may be null) with `changes` (sorted by point, distinct) merged in; points that end up
/// with the base colour are dropped, so the layer stays canonical. Null when nothing is left.
adf::ColourTilePtr merged(const adf::ColourTile* old, const std::vector<std::pair<uint32_t, adf::Rgb8>>& changes,
                          adf::Rgb8 base) {
    std::vector<uint32_t> points;
    std::vector<adf::Rgb8> colours;
    const std::size_t oldSize = old ? old->size() : 0;
    points.reserve(oldSize + changes.size());
    colours.reserve(oldSize + changes.size());
    auto push = [&](uint32_t p, adf::Rgb8 c) {
        if (c == base) return;
        points.push_back(p);
        colours.push_back(c);
    };
    std::size_t i = 0, j = 0;
    while (i < oldSize || j < changes.size()) {
        if (j == changes.size() || (i < oldSize && old->points()[i] < changes[j].first)) {
            push(old->points()[i], old->colours()[i]);
            ++i;
            continue;
        }
        if (i < oldSize && old->points()[i] == changes[j].first) ++i;
        push(changes[j].first, changes[j].second);
        ++j;
    }
    if (points.empty()) return nullptr;
    return std::make_shared<const adf::ColourTile>(std::move(points), std::move(colours));
}

}  // namespace

adf::ColourLayerPtr paintStroke(const adf::Adf& adf, const Stroke& stroke, util::ThreadPool* pool, PaintStats* stats) {
    if (stroke.tool.op != ToolOp::Paint) throw std::invalid_argument("paintStroke needs a paint stroke");
    // The strength is the paint's opacity, not a smaller tool.
    Tool shape = stroke.tool;
    shape.strength = 1.0;
    const auto swept = makeSweptTool(shape, stroke.samples);
    const adf::Domain& d = adf.domain();
    // Masks work like masking tape: no paint inside them, a sharp edge at theirs.
    std::vector<adf::SourcePtr> masks;
    for (const Shape& m : stroke.constraints.masks) masks.push_back(m.source(d));
    const double h = d.finestCellSize();
    const double core = 0.5 * (shape.shape == ToolShape::Cylinder ? std::min(shape.radius, shape.halfLength) : shape.radius);
    const double opacity = stroke.tool.strength;
    const float band = float(kPaintBandCells * h);
    const adf::Rgb8 paint = stroke.tool.colour;
    const glm::dvec3 centre = d.originWorld + glm::dvec3(0.5 * d.sizeWorld);
    const uint32_t span = uint32_t(d.tileSpan());

    adf::ColourLayerPtr layer = adf.colours() ? adf.colours() : std::make_shared<const adf::ColourLayer>(d);
    const adf::Rgb8 base = layer->baseColour();
    PaintStats total;
    for (uint8_t reflect = 0; reflect < 8; ++reflect) {
        if ((reflect & ~stroke.mirror) != 0) continue;
        // The copy's box (the tool mirrored) in lattice points, clipped to the domain.
        const adf::BoxWorld bounds = mirroredBox(swept->bounds(), reflect, centre);
        glm::uvec3 pMin, pMax;
        if (!latticeBox(d, bounds, pMin, pMax)) continue;
        std::vector<glm::uvec3> slots;
        for (uint32_t z = pMin.z >> span; z <= pMax.z >> span; ++z)
            for (uint32_t y = pMin.y >> span; y <= pMax.y >> span; ++y)
                for (uint32_t x = pMin.x >> span; x <= pMax.x >> span; ++x) slots.push_back({x, y, z});

        struct Result {
            bool changed = false;
            adf::ColourTilePtr tile;
            std::size_t points = 0, replacedBytes = 0;
        };
        std::vector<Result> results(slots.size());
        util::parallelFor(pool, slots.size(), [&](std::size_t i) {
            const uint32_t key = layer->slotKey(slots[i]);
            const adf::ColourTile* old = layer->tileAt(key);
            const glm::uvec3 s0 = slots[i] << span;
            const glm::uvec3 a = glm::max(pMin, s0), b = glm::min(pMax, s0 + ((1u << span) - 1u)) + 1u;  // [a, b)
            std::vector<std::pair<uint32_t, adf::Rgb8>> changes;
            forEachBandPoint(adf, slots[i], a, b, band, [&](glm::uvec3 pl, uint32_t local) {
                const glm::dvec3 p = d.latticeToWorld(pl.x, pl.y, pl.z);
                if (std::any_of(masks.begin(), masks.end(), [&](const adf::SourcePtr& m) { return m->distance(p) < 0.0; }))
                    return;
                const glm::dvec3 q = mirroredPoint(p, reflect, centre);  // the point, not the tool
                const double w = toolWeight(-swept->distanceBelow(q, 0.0), core);
                if (w <= 0.0) return;
                const adf::Rgb8* had = old ? old->find(local) : nullptr;
                const adf::Rgb8 from = had ? *had : base;
                const adf::Rgb8 to = mixColour(from, paint, w * opacity);
                if (to != from) changes.emplace_back(local, to);
            });
            // Leaves come depth first; every point once, so sorting by index is deterministic.
            std::sort(changes.begin(), changes.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
            if (changes.empty()) return;
            results[i] = {true, merged(old, changes, base), changes.size(), old ? old->bytes() : 0};
        });
        std::vector<std::pair<uint32_t, adf::ColourTilePtr>> replaced;
        for (std::size_t i = 0; i < slots.size(); ++i) {
            if (!results[i].changed) continue;
            replaced.emplace_back(layer->slotKey(slots[i]), std::move(results[i].tile));
            total.pointsChanged += results[i].points;
            total.replacedBytes += results[i].replacedBytes;
        }
        if (replaced.empty()) continue;
        total.slotsPainted += replaced.size();
        total.replacedBytes += layer->slotCount() * (sizeof(uint32_t) + sizeof(adf::ColourTilePtr));
        layer = layer->withTiles(std::move(replaced));
    }
    if (stats) *stats = total;
    if (!total.slotsPainted) return adf.colours();
    // Painting clay colour over all the paint there was leaves none: an unpainted snapshot.
    return layer->slotCount() ? layer : nullptr;
}

adf::ColourLayerPtr paintLiveSegment(const adf::Adf& adf, const Stroke& header, const adf::ColourLayer* start,
                                     std::span<const ToolSample> before, std::span<const ToolSample> segment,
                                     util::ThreadPool* pool, PaintStats* stats) {
    if (header.tool.op != ToolOp::Paint) throw std::invalid_argument("paintLiveSegment needs a paint stroke");
    Tool shape = header.tool;
    shape.strength = 1.0;  // the opacity, as in paintStroke
    const auto segTool = makeSweptTool(shape, std::vector<ToolSample>(segment.begin(), segment.end()));
    const std::shared_ptr<const SweptTool> beforeTool =
        before.empty() ? nullptr : makeSweptTool(shape, std::vector<ToolSample>(before.begin(), before.end()));
    const adf::Domain& d = adf.domain();
    std::vector<adf::SourcePtr> masks;
    for (const Shape& m : header.constraints.masks) masks.push_back(m.source(d));
    const double h = d.finestCellSize();
    const double core = 0.5 * (shape.shape == ToolShape::Cylinder ? std::min(shape.radius, shape.halfLength) : shape.radius);
    const double opacity = header.tool.strength;
    const float band = float(kPaintBandCells * h);
    const adf::Rgb8 paint = header.tool.colour;
    const glm::dvec3 centre = d.originWorld + glm::dvec3(0.5 * d.sizeWorld);
    const uint32_t span = uint32_t(d.tileSpan());

    const adf::ColourLayerPtr layer = adf.colours() ? adf.colours() : std::make_shared<const adf::ColourLayer>(d);
    const adf::Rgb8 base = layer->baseColour();
    // The mirrored copies in apply()'s order, each with the segment's box in lattice points.
    struct Copy {
        uint8_t reflect;
        glm::uvec3 pMin, pMax;
    };
    std::vector<Copy> copies;
    std::vector<uint8_t> all;
    std::vector<uint32_t> keys;
    for (uint8_t reflect = 0; reflect < 8; ++reflect) {
        if ((reflect & ~header.mirror) != 0) continue;
        all.push_back(reflect);
        Copy c{reflect, {}, {}};
        if (!latticeBox(d, mirroredBox(segTool->bounds(), reflect, centre), c.pMin, c.pMax)) continue;
        copies.push_back(c);
        for (uint32_t z = c.pMin.z >> span; z <= c.pMax.z >> span; ++z)
            for (uint32_t y = c.pMin.y >> span; y <= c.pMax.y >> span; ++y)
                for (uint32_t x = c.pMin.x >> span; x <= c.pMax.x >> span; ++x) keys.push_back(layer->slotKey({x, y, z}));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    const uint32_t n = d.slotsPerAxis();

    struct Result {
        bool changed = false;
        adf::ColourTilePtr tile;
        std::size_t points = 0, replacedBytes = 0;
    };
    std::vector<Result> results(keys.size());
    util::parallelFor(pool, keys.size(), [&](std::size_t i) {
        const glm::uvec3 slot(keys[i] % n, (keys[i] / n) % n, keys[i] / (n * n));
        const adf::ColourTile* old = layer->tileAt(keys[i]);
        const adf::ColourTile* was = start ? start->tileAt(keys[i]) : nullptr;
        const glm::uvec3 s0 = slot << span, s1 = s0 + ((1u << span) - 1u);
        // [a, b): the slot's part of every copy's box.
        glm::uvec3 a(~0u), b(0u);
        for (const Copy& c : copies) {
            const glm::uvec3 ca = glm::max(c.pMin, s0), cb = glm::min(c.pMax, s1);
            if (glm::any(glm::greaterThan(ca, cb))) continue;
            a = glm::min(a, ca);
            b = glm::max(b, cb + 1u);
        }
        if (glm::any(glm::greaterThanEqual(a, b))) return;
        std::vector<std::pair<uint32_t, adf::Rgb8>> changes;
        forEachBandPoint(adf, slot, a, b, band, [&](glm::uvec3 pl, uint32_t local) {
            const glm::dvec3 p = d.latticeToWorld(pl.x, pl.y, pl.z);
            // The segment's weight in each copy; nothing to do where it is 0 in all.
            std::array<double, 8> wSeg{};
            bool touched = false;
            for (const Copy& c : copies) {
                if (glm::any(glm::lessThan(pl, c.pMin)) || glm::any(glm::greaterThan(pl, c.pMax))) continue;
                wSeg[c.reflect] = toolWeight(-segTool->distanceBelow(mirroredPoint(p, c.reflect, centre), 0.0), core);
                touched = touched || wSeg[c.reflect] > 0.0;
            }
            if (!touched) return;
            // The running maximum weight per copy; the point changes only where one grows.
            std::array<double, 8> wNow{};
            bool grew = false;
            for (uint8_t r : all) {
                const double wBefore =
                    beforeTool ? toolWeight(-beforeTool->distanceBelow(mirroredPoint(p, r, centre), 0.0), core) : 0.0;
                grew = grew || wSeg[r] > wBefore;
                wNow[r] = std::max(wSeg[r], wBefore);
            }
            if (!grew) return;
            if (std::any_of(masks.begin(), masks.end(), [&](const adf::SourcePtr& m) { return m->distance(p) < 0.0; })) return;
            // apply()'s blend: from the start's colour, each copy in turn.
            const adf::Rgb8* had = was ? was->find(local) : nullptr;
            adf::Rgb8 to = had ? *had : base;
            for (uint8_t r : all)
                if (wNow[r] > 0.0) to = mixColour(to, paint, wNow[r] * opacity);
            const adf::Rgb8* has = old ? old->find(local) : nullptr;
            if (to != (has ? *has : base)) changes.emplace_back(local, to);
        });
        std::sort(changes.begin(), changes.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
        if (changes.empty()) return;
        results[i] = {true, merged(old, changes, base), changes.size(), old ? old->bytes() : 0};
    });
    std::vector<std::pair<uint32_t, adf::ColourTilePtr>> replaced;
    PaintStats total;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        if (!results[i].changed) continue;
        replaced.emplace_back(keys[i], std::move(results[i].tile));
        total.pointsChanged += results[i].points;
        total.replacedBytes += results[i].replacedBytes;
    }
    if (!replaced.empty()) {
        total.slotsPainted = replaced.size();
        total.replacedBytes += layer->slotCount() * (sizeof(uint32_t) + sizeof(adf::ColourTilePtr));
    }
    if (stats) *stats = total;
    if (replaced.empty()) return adf.colours();
    const adf::ColourLayerPtr out = layer->withTiles(std::move(replaced));
    return out->slotCount() ? out : nullptr;
}

PaintStats paintedBetween(const adf::ColourLayer* before, const adf::ColourLayer* after) {
    PaintStats out;
    if (before == after) return out;
    const std::span<const uint32_t> bk = before ? before->slotKeys() : std::span<const uint32_t>();
    const std::span<const uint32_t> ak = after ? after->slotKeys() : std::span<const uint32_t>();
    std::size_t i = 0, j = 0;
    while (i < bk.size() || j < ak.size()) {
        if (j == ak.size() || (i < bk.size() && bk[i] < ak[j])) {  // unpainted now
            ++out.slotsPainted;
            out.replacedBytes += before->tiles()[i]->bytes();
            ++i;
        } else if (i == bk.size() || ak[j] < bk[i]) {  // painted anew
            ++out.slotsPainted;
            ++j;
        } else {
            if (before->tiles()[i] != after->tiles()[j]) {
                ++out.slotsPainted;
                out.replacedBytes += before->tiles()[i]->bytes();
            }
            ++i;
            ++j;
        }
    }
    if (out.slotsPainted && before) out.replacedBytes += before->slotCount() * (sizeof(uint32_t) + sizeof(adf::ColourTilePtr));
    return out;
}

}  // namespace kizamu::sculpt
