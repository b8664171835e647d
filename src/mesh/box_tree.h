// SPDX-License-Identifier: Apache-2.0
/// @file box_tree.h
/// @brief A static bounding-volume hierarchy over axis-aligned boxes: which of them pass a box
/// test (meet a box, hold a box), without looking at most of them.
///
/// Median splits along the widest axis of the box centres, four boxes a leaf; adapts to boxes of
/// very different sizes (an adaptive mesh's flat regions and fine details, a scan's many small
/// parts), which a uniform grid does not. The test must pass a node's box whenever it passes a
/// box inside it (meeting or holding a fixed box both do). Built once, then only read: any number
/// of threads may visit it.
/// Complexity: O(n log n) to build; a visit O(log n + k) when k boxes pass and few nodes do.
#pragma once

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

namespace kizamu::mesh {

/// An axis-aligned box in doubles; empty (holds nothing) until a point is added.
struct Box3 {
    glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
    void add(const glm::dvec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    /// The closed boxes meet (touching counts).
    bool meets(const Box3& o) const {
        return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y && lo.z <= o.hi.z && o.lo.z <= hi.z;
    }
    bool holds(const Box3& o) const {
        return lo.x <= o.lo.x && lo.y <= o.lo.y && lo.z <= o.lo.z && o.hi.x <= hi.x && o.hi.y <= hi.y && o.hi.z <= hi.z;
    }
};

class BoxTree {
public:
    /// Over boxes[i] for each i in `items` (the boxes are referenced, not copied: they must
    /// outlive the tree).
    BoxTree(const std::vector<Box3>& boxes, std::vector<uint32_t> items) : mBoxes(boxes), mItems(std::move(items)) {
        if (mItems.empty()) return;
        mNodes.reserve(2 * mItems.size() / kLeaf + 2);
        mNodes.emplace_back();
        build(0, 0, uint32_t(mItems.size()));
    }
    /// Over every box.
    explicit BoxTree(const std::vector<Box3>& boxes) : BoxTree(boxes, allOf(boxes.size())) {}

    /// Calls f(item) for each item whose box passes `test(const Box3&)`.
    template <class Test, class F>
    void visit(Test&& test, F&& f) const {
        if (mNodes.empty()) return;
        uint32_t stack[64];  // the depth is about log2(n / kLeaf) + 1
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& n = mNodes[stack[--top]];
            if (!test(n.box)) continue;
            if (n.count > 0) {
                for (uint32_t i = n.first; i < n.first + n.count; ++i)
                    if (test(mBoxes[mItems[i]])) f(mItems[i]);
            } else {
                stack[top++] = n.first;
                stack[top++] = n.first + 1;
            }
        }
    }

private:
    static constexpr uint32_t kLeaf = 4;
    struct Node {
        Box3 box;
        uint32_t first = 0;  ///< a leaf's first entry of mItems, else its first child (the second follows)
        uint32_t count = 0;  ///< a leaf's boxes; 0 for an inner node
    };
    static std::vector<uint32_t> allOf(std::size_t n) {
        std::vector<uint32_t> items(n);
        std::iota(items.begin(), items.end(), 0u);
        return items;
    }
    /// Fills node `at` with mItems[begin, end); children are made in pairs.
    void build(uint32_t at, uint32_t begin, uint32_t end) {
        Box3 box, centres;
        for (uint32_t i = begin; i < end; ++i) {
            const Box3& b = mBoxes[mItems[i]];
            box.add(b.lo);
            box.add(b.hi);
            centres.add(b.lo + b.hi);
        }
        mNodes[at].box = box;
        if (end - begin <= kLeaf) {
            mNodes[at].first = begin;
            mNodes[at].count = end - begin;
            return;
        }
        const glm::dvec3 e = centres.hi - centres.lo;
        const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(mItems.begin() + begin, mItems.begin() + mid, mItems.begin() + end, [&](uint32_t l, uint32_t r) {
            return mBoxes[l].lo[axis] + mBoxes[l].hi[axis] < mBoxes[r].lo[axis] + mBoxes[r].hi[axis];
        });
        const auto left = uint32_t(mNodes.size());
        mNodes.resize(mNodes.size() + 2);
        mNodes[at].first = left;
        build(left, begin, mid);
        build(left + 1, mid, end);
    }

    const std::vector<Box3>& mBoxes;
    std::vector<uint32_t> mItems;
    std::vector<Node> mNodes;
};

}  // namespace kizamu::mesh
