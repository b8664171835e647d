// SPDX-License-Identifier: Apache-2.0
/// @file distance_source.cpp
/// @brief Closed-form primitive distances, rigid transforms and (smooth) CSG nodes.
#include "adf/distance_source.h"

#include "adf/domain.h"

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace kizamu::adf {

void DistanceSource::distances(std::span<const glm::dvec3> pWorld, std::span<double> out) const {
    assert(pWorld.size() == out.size());
    for (std::size_t i = 0; i < pWorld.size(); ++i) out[i] = distance(pWorld[i]);
}

bool DistanceSource::answersLattice(const Domain&) const { return false; }

void DistanceSource::latticeDistances(const Domain& domain, std::span<const glm::uvec3> lattice,
                                      std::span<double> out) const {
    assert(lattice.size() == out.size());
    glm::dvec3 world[kSourceBatch];
    for (std::size_t first = 0; first < lattice.size(); first += kSourceBatch) {
        const std::size_t n = std::min(kSourceBatch, lattice.size() - first);
        for (std::size_t i = 0; i < n; ++i) {
            const glm::uvec3 p = lattice[first + i];
            world[i] = domain.latticeToWorld(p.x, p.y, p.z);
        }
        distances({world, n}, out.subspan(first, n));
    }
}

double DistanceSource::featureSize(const glm::dvec3&, double) const {
    return std::numeric_limits<double>::infinity();
}

DistanceSource::Range DistanceSource::unchangedRange(const glm::dvec3&, double) const { return {}; }

namespace {

/// Shared batch loop for primitives: one virtual call per batch, the scalar form inlined.
/// `Derived::size()` is the primitive's smallest feature, m.
template <class Derived>
class Primitive : public DistanceSource {
public:
    double distance(const glm::dvec3& p) const final {
        return static_cast<const Derived*>(this)->eval(p);
    }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const final {
        const auto& self = *static_cast<const Derived*>(this);
        for (std::size_t i = 0; i < p.size(); ++i) out[i] = self.eval(p[i]);
    }
    double featureSize(const glm::dvec3& c, double radius) const final {
        const auto& self = *static_cast<const Derived*>(this);
        return std::abs(self.eval(c)) <= radius ? self.size() : std::numeric_limits<double>::infinity();
    }
    /// Builds a Derived and records its feature size (which needs the finished object).
    template <class... Args>
    static SourcePtr make(Args&&... args) {
        auto p = std::make_shared<Derived>(std::forward<Args>(args)...);
        p->mSmallestFeature = p->size();
        return p;
    }
};

double maxComponent(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

double boxDistance(const glm::dvec3& p, const glm::dvec3& halfSize) {
    const glm::dvec3 q = glm::abs(p) - halfSize;
    return glm::length(glm::max(q, glm::dvec3(0.0))) + std::min(maxComponent(q), 0.0);
}

class Sphere final : public Primitive<Sphere> {
public:
    explicit Sphere(double r) : mRadius(r) {}
    double eval(const glm::dvec3& p) const { return glm::length(p) - mRadius; }
    double size() const { return mRadius; }

private:
    double mRadius;
};

class Box final : public Primitive<Box> {
public:
    explicit Box(const glm::dvec3& h) : mHalf(h) {}
    double eval(const glm::dvec3& p) const { return boxDistance(p, mHalf); }
    double size() const { return std::min({mHalf.x, mHalf.y, mHalf.z}); }

private:
    glm::dvec3 mHalf;
};

class RoundedBox final : public Primitive<RoundedBox> {
public:
    RoundedBox(const glm::dvec3& h, double r) : mInner(h - glm::dvec3(r)), mRadius(r) {}
    double eval(const glm::dvec3& p) const { return boxDistance(p, mInner) - mRadius; }
    double size() const {
        const double half = std::min({mInner.x, mInner.y, mInner.z}) + mRadius;
        return mRadius > 0.0 ? std::min(half, mRadius) : half;
    }

private:
    glm::dvec3 mInner;
    double mRadius;
};

class Capsule final : public Primitive<Capsule> {
public:
    Capsule(const glm::dvec3& a, const glm::dvec3& b, double r)
        : mA(a), mAxis(b - a), mInvLen2(glm::dot(b - a, b - a) > 0 ? 1.0 / glm::dot(b - a, b - a) : 0.0),
          mRadius(r) {}
    double eval(const glm::dvec3& p) const {
        const glm::dvec3 ap = p - mA;
        const double t = std::clamp(glm::dot(ap, mAxis) * mInvLen2, 0.0, 1.0);
        return glm::length(ap - mAxis * t) - mRadius;
    }
    double size() const { return mRadius; }

private:
    glm::dvec3 mA, mAxis;
    double mInvLen2, mRadius;
};

class Cylinder final : public Primitive<Cylinder> {
public:
    Cylinder(double r, double h) : mRadius(r), mHalfHeight(h) {}
    double eval(const glm::dvec3& p) const {
        const double dx = std::sqrt(p.x * p.x + p.y * p.y) - mRadius;
        const double dz = std::abs(p.z) - mHalfHeight;
        const double ox = std::max(dx, 0.0), oz = std::max(dz, 0.0);
        return std::min(std::max(dx, dz), 0.0) + std::sqrt(ox * ox + oz * oz);
    }
    double size() const { return std::min(mRadius, mHalfHeight); }

private:
    double mRadius, mHalfHeight;
};

class Torus final : public Primitive<Torus> {
public:
    Torus(double major, double minor) : mMajor(major), mMinor(minor) {}
    double eval(const glm::dvec3& p) const {
        const double ring = std::sqrt(p.x * p.x + p.y * p.y) - mMajor;
        return std::sqrt(ring * ring + p.z * p.z) - mMinor;
    }
    double size() const { return mMinor; }

private:
    double mMajor, mMinor;
};

class HalfSpace final : public Primitive<HalfSpace> {
public:
    HalfSpace(const glm::dvec3& n, double offset) : mNormal(n), mOffset(offset) {}
    double eval(const glm::dvec3& p) const { return glm::dot(p, mNormal) - mOffset; }
    double size() const { return std::numeric_limits<double>::infinity(); }

private:
    glm::dvec3 mNormal;
    double mOffset;
};

class Transformed final : public DistanceSource {
public:
    Transformed(SourcePtr child, const glm::dvec3& t, const glm::dquat& r, double s)
        : mChild(std::move(child)), mTranslation(t),
          mInverseRotation(glm::mat3_cast(glm::conjugate(glm::normalize(r)))), mScale(s),
          mTranslationOnly(s == 1.0 && mInverseRotation == glm::dmat3(1.0)) {
        mSmallestFeature = mScale * mChild->smallestFeature();
    }

    double distance(const glm::dvec3& p) const override {
        return mScale * mChild->distance(toLocal(p));
    }
    double featureSize(const glm::dvec3& c, double radius) const override {
        return mScale * mChild->featureSize(toLocal(c), radius / mScale);
    }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        glm::dvec3 local[kSourceBatch];
        for (std::size_t begin = 0; begin < p.size(); begin += kSourceBatch) {
            const std::size_t n = std::min(kSourceBatch, p.size() - begin);
            for (std::size_t i = 0; i < n; ++i) local[i] = toLocal(p[begin + i]);
            mChild->distances({local, n}, out.subspan(begin, n));
            if (mScale != 1.0)
                for (std::size_t i = 0; i < n; ++i) out[begin + i] *= mScale;
        }
    }

private:
    glm::dvec3 toLocal(const glm::dvec3& p) const {
        if (mTranslationOnly) return p - mTranslation;
        return (mInverseRotation * (p - mTranslation)) / mScale;
    }
    SourcePtr mChild;
    glm::dvec3 mTranslation;
    glm::dmat3 mInverseRotation;
    double mScale;
    bool mTranslationOnly;  ///< skips the matrix for the common pure translation
};

/// Polynomial smooth minimum (quadratic): equals min(a, b) once |a - b| >= k.
double smoothMin(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * k * 0.25;
}

class Csg final : public DistanceSource {
public:
    Csg(CsgOp op, SourcePtr a, SourcePtr b, double k)
        : mOp(op), mA(std::move(a)), mB(std::move(b)), mBlend(k) {
        mSmallestFeature = std::min({mA->smallestFeature(), mB->smallestFeature(),
                                     k > 0.0 ? k : std::numeric_limits<double>::infinity()});
    }

    double distance(const glm::dvec3& p) const override {
        return combine(mA->distance(p), mB->distance(p));
    }
    double featureSize(const glm::dvec3& c, double radius) const override {
        const double blend = mBlend > 0.0 ? mBlend : std::numeric_limits<double>::infinity();
        return std::min({mA->featureSize(c, radius), mB->featureSize(c, radius), blend});
    }
    void distances(std::span<const glm::dvec3> p, std::span<double> out) const override {
        double other[kSourceBatch];
        for (std::size_t begin = 0; begin < p.size(); begin += kSourceBatch) {
            const std::size_t n = std::min(kSourceBatch, p.size() - begin);
            const auto pts = p.subspan(begin, n);
            const auto dst = out.subspan(begin, n);
            mA->distances(pts, dst);
            mB->distances(pts, {other, n});
            for (std::size_t i = 0; i < n; ++i) dst[i] = combine(dst[i], other[i]);
        }
    }

private:
    double combine(double a, double b) const {
        if (mBlend > 0.0) {
            switch (mOp) {
                case CsgOp::Union: return smoothMin(a, b, mBlend);
                case CsgOp::Intersection: return -smoothMin(-a, -b, mBlend);
                case CsgOp::Difference: return -smoothMin(-a, b, mBlend);
            }
        }
        switch (mOp) {
            case CsgOp::Union: return std::min(a, b);
            case CsgOp::Intersection: return std::max(a, b);
            case CsgOp::Difference: return std::max(a, -b);
        }
        return a;
    }
    CsgOp mOp;
    SourcePtr mA, mB;
    double mBlend;
};

void requirePositive(double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string(what) + " must be positive and finite");
}

}  // namespace

SourcePtr makeSphere(double radius) {
    requirePositive(radius, "sphere radius");
    return Primitive<Sphere>::make(radius);
}
SourcePtr makeBox(const glm::dvec3& halfSize) {
    requirePositive(std::min({halfSize.x, halfSize.y, halfSize.z}), "box half size");
    return Primitive<Box>::make(halfSize);
}
SourcePtr makeRoundedBox(const glm::dvec3& halfSize, double cornerRadius) {
    requirePositive(std::min({halfSize.x, halfSize.y, halfSize.z}), "rounded box half size");
    if (!(cornerRadius >= 0.0) || cornerRadius > std::min({halfSize.x, halfSize.y, halfSize.z}))
        throw std::invalid_argument("rounded box corner radius must lie in [0, smallest half size]");
    return Primitive<RoundedBox>::make(halfSize, cornerRadius);
}
SourcePtr makeCapsule(const glm::dvec3& a, const glm::dvec3& b, double radius) {
    requirePositive(radius, "capsule radius");
    return Primitive<Capsule>::make(a, b, radius);
}
SourcePtr makeCylinder(double radius, double halfHeight) {
    requirePositive(radius, "cylinder radius");
    requirePositive(halfHeight, "cylinder half height");
    return Primitive<Cylinder>::make(radius, halfHeight);
}
SourcePtr makeTorus(double majorRadius, double minorRadius) {
    requirePositive(majorRadius, "torus major radius");
    requirePositive(minorRadius, "torus minor radius");
    return Primitive<Torus>::make(majorRadius, minorRadius);
}
SourcePtr makeHalfSpace(const glm::dvec3& normal, double offset) {
    const double len = glm::length(normal);
    requirePositive(len, "half-space normal length");
    return Primitive<HalfSpace>::make(normal / len, offset);
}
SourcePtr makeTransformed(SourcePtr child, const glm::dvec3& translation, const glm::dquat& rotation,
                          double scale) {
    if (!child) throw std::invalid_argument("transformed source is null");
    requirePositive(scale, "transform scale");
    return std::make_shared<Transformed>(std::move(child), translation, rotation, scale);
}
SourcePtr makeTranslated(SourcePtr child, const glm::dvec3& translation) {
    return makeTransformed(std::move(child), translation);
}
SourcePtr makeCsg(CsgOp op, SourcePtr a, SourcePtr b, double blendRadius) {
    if (!a || !b) throw std::invalid_argument("CSG operand is null");
    if (!(blendRadius >= 0.0)) throw std::invalid_argument("CSG blend radius must be >= 0");
    return std::make_shared<Csg>(op, std::move(a), std::move(b), blendRadius);
}
SourcePtr makeCsg(CsgOp op, const std::vector<SourcePtr>& parts, double blendRadius) {
    if (parts.empty()) throw std::invalid_argument("CSG needs at least one operand");
    SourcePtr acc = parts.front();
    for (std::size_t i = 1; i < parts.size(); ++i) acc = makeCsg(op, acc, parts[i], blendRadius);
    return acc;
}

}  // namespace kizamu::adf
