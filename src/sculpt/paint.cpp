// SPDX-License-Identifier: Apache-2.0
/// @file paint.cpp
/// @brief paintStroke: colour tiles rewritten where a swept tool meets the surface.
#include "sculpt/paint.h"

#include "sculpt/swept_tool.h"
#include "sculpt/symmetry.h"
#include "util/thread_pool.h"

#include <glm/common.hpp>

#include <algorithm>
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
    const uint32_t span = uint32_t(d.tileSpan()), last = d.latticeSize() - 1;

    adf::ColourLayerPtr layer = adf.colours() ? adf.colours() : std::make_shared<const adf::ColourLayer>(d);
    const adf::Rgb8 base = layer->baseColour();
    PaintStats total;
    for (uint8_t reflect = 0; reflect < 8; ++reflect) {
        if ((reflect & ~stroke.mirror) != 0) continue;
        // The copy's box (the tool mirrored) in lattice points, clipped to the domain.
        const adf::BoxWorld bounds = mirroredBox(swept->bounds(), reflect, centre);
        const glm::dvec3 lo = glm::ceil((bounds.min - d.originWorld) / h), hi = glm::floor((bounds.max - d.originWorld) / h);
        if (glm::any(glm::greaterThan(lo, hi)) || glm::any(glm::lessThan(hi, glm::dvec3(0.0))) ||
            glm::any(glm::greaterThan(lo, glm::dvec3(last))))
            continue;
        const glm::uvec3 pMin(glm::clamp(lo, glm::dvec3(0.0), glm::dvec3(last)));
        const glm::uvec3 pMax(glm::clamp(hi, glm::dvec3(0.0), glm::dvec3(last)));
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
            // Leaf by leaf: a trilinear cell lies between its corners' values, so a leaf whose
            // corners are all beyond the band on one side holds no band point (most of the box).
            // Each lattice point belongs to the one leaf whose half-open box holds it, as in
            // Adf::findLeaf, so its field value is the one a lookup gives.
            adf::forEachLeaf(*adf.tileAtSlot(slots[i]), d.maxLevel, [&](const adf::LeafRef& leaf) {
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
                            const glm::dvec3 p = d.latticeToWorld(x, y, z);
                            if (std::any_of(masks.begin(), masks.end(), [&](const adf::SourcePtr& m) { return m->distance(p) < 0.0; }))
                                continue;
                            const glm::dvec3 q = mirroredPoint(p, reflect, centre);  // the point, not the tool
                            const double w = toolWeight(-swept->distanceBelow(q, 0.0), core);
                            if (w <= 0.0) continue;
                            const uint32_t local = ((z - s0.z) << (2 * span)) | ((y - s0.y) << span) | (x - s0.x);
                            const adf::Rgb8* had = old ? old->find(local) : nullptr;
                            const adf::Rgb8 from = had ? *had : base;
                            const double alpha = w * opacity;
                            const adf::Rgb8 to(mixChannel(from.r, paint.r, alpha), mixChannel(from.g, paint.g, alpha),
                                               mixChannel(from.b, paint.b, alpha));
                            if (to != from) changes.emplace_back(local, to);
                        }
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

}  // namespace kizamu::sculpt
