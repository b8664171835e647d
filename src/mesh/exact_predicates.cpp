// SPDX-License-Identifier: Apache-2.0
/// @file exact_predicates.cpp
/// @brief Filtered orientation signs with an exact integer fallback.
#include "mesh/exact_predicates.h"

#include <boost/multiprecision/cpp_int.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace kizamu::mesh::exact {

namespace {

using Integer = boost::multiprecision::cpp_int;

constexpr double kEps = std::numeric_limits<double>::epsilon() / 2.0;  // 2^-53, Shewchuk's epsilon
constexpr double kBound2 = (3.0 + 16.0 * kEps) * kEps;
constexpr double kBound3 = (7.0 + 56.0 * kEps) * kEps;

/// Finite doubles as exact integers on one common scale: value = integer * 2^shift, where
/// shift is the smallest exponent among them (so no division is ever needed).
template <std::size_t N>
std::array<Integer, N> onCommonScale(const std::array<double, N>& v) {
    int shift = std::numeric_limits<int>::max();
    std::array<int64_t, N> mantissa{};
    std::array<int, N> exponent{};
    for (std::size_t i = 0; i < N; ++i) {
        int e = 0;
        const double m = std::frexp(v[i], &e);  // v = m * 2^e, 0.5 <= |m| < 1
        mantissa[i] = int64_t(std::ldexp(m, 53));
        exponent[i] = e - 53;
        if (mantissa[i] != 0) shift = std::min(shift, exponent[i]);
    }
    std::array<Integer, N> out;
    for (std::size_t i = 0; i < N; ++i) {
        out[i] = mantissa[i];
        if (mantissa[i] != 0) out[i] <<= unsigned(exponent[i] - shift);
    }
    return out;
}

int signOf(const Integer& r) { return r.sign(); }

}  // namespace

int orient3d(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
    const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
    const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
    const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const double cdxady = cdx * ady, adxcdy = adx * cdy;
    const double adxbdy = adx * bdy, bdxady = bdx * ady;
    const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                             (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                             (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
    const double bound = kBound3 * permanent;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    if (permanent == 0.0) return 0;  // every product is exactly zero
    const auto [ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz] =
        onCommonScale<12>({a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z, d.x, d.y, d.z});
    const Integer rax = ax - dx, rbx = bx - dx, rcx = cx - dx;
    const Integer ray = ay - dy, rby = by - dy, rcy = cy - dy;
    const Integer raz = az - dz, rbz = bz - dz, rcz = cz - dz;
    return signOf(raz * (rbx * rcy - rcx * rby) + rbz * (rcx * ray - rax * rcy) + rcz * (rax * rby - rbx * ray));
}

int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    const double left = (a.x - c.x) * (b.y - c.y), right = (a.y - c.y) * (b.x - c.x);
    const double det = left - right;
    const double bound = kBound2 * (std::abs(left) + std::abs(right));
    if (det > bound) return 1;
    if (-det > bound) return -1;
    if (left == 0.0 && right == 0.0) return 0;
    const auto [ax, ay, bx, by, cx, cy] = onCommonScale<6>({a.x, a.y, b.x, b.y, c.x, c.y});
    return signOf((ax - cx) * (by - cy) - (ay - cy) * (bx - cx));
}

}  // namespace kizamu::mesh::exact
