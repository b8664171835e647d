// SPDX-License-Identifier: Apache-2.0
#include "xr/stylus_registration.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace kizamu::xr {

namespace {

using Matrix4 = std::array<std::array<double, 4>, 4>;

/// The unit eigenvector of the largest eigenvalue of symmetric `a` (cyclic Jacobi rotations).
std::array<double, 4> dominantEigenvector(Matrix4 a) {
    Matrix4 v{};
    for (int i = 0; i < 4; ++i) v[i][i] = 1.0;
    for (int sweep = 0; sweep < 64; ++sweep) {
        double off = 0.0;
        for (int p = 0; p < 4; ++p)
            for (int q = p + 1; q < 4; ++q) off += a[p][q] * a[p][q];
        if (off < 1e-30) break;
        for (int p = 0; p < 4; ++p) {
            for (int q = p + 1; q < 4; ++q) {
                if (std::abs(a[p][q]) < 1e-300) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 4; ++k) {  // columns p, q
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 4; ++k) {  // rows p, q
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 4; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    int best = 0;
    for (int i = 1; i < 4; ++i)
        if (a[i][i] > a[best][best]) best = i;
    return {v[0][best], v[1][best], v[2][best], v[3][best]};
}

}  // namespace

StylusRegistration registerStylus(std::span<const glm::dvec3> device, std::span<const glm::dvec3> space) {
    if (device.size() != space.size())
        throw std::invalid_argument("stylus registration: " + std::to_string(device.size()) + " stylus points but " +
                                    std::to_string(space.size()) + " controller points");
    if (device.size() < 3) throw std::invalid_argument("stylus registration needs at least three points touched with both");
    const double n = double(device.size());
    glm::dvec3 ca(0.0), cb(0.0);
    for (std::size_t i = 0; i < device.size(); ++i) {
        ca += device[i] / n;
        cb += space[i] / n;
    }
    double spreadA = 0.0, spreadB = 0.0, area = 0.0;
    double s[3][3] = {};
    for (std::size_t i = 0; i < device.size(); ++i) {
        const glm::dvec3 a = device[i] - ca, b = space[i] - cb;
        spreadA += glm::dot(a, a);
        spreadB += glm::dot(b, b);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) s[r][c] += a[r] * b[c];
        for (std::size_t j = 0; j < i; ++j) area = std::max(area, glm::length(glm::cross(a, device[j] - ca)));
    }
    // Points on one line leave the turn about it undetermined.
    if (spreadA < 1e-12 || area < 1e-3 * spreadA / n)
        throw std::invalid_argument("stylus registration: the points touched lie on one line; touch three corners of a triangle");

    const double sxx = s[0][0], sxy = s[0][1], sxz = s[0][2], syx = s[1][0], syy = s[1][1], syz = s[1][2];
    const double szx = s[2][0], szy = s[2][1], szz = s[2][2];
    const Matrix4 nMatrix{{{sxx + syy + szz, syz - szy, szx - sxz, sxy - syx},
                           {syz - szy, sxx - syy - szz, sxy + syx, szx + sxz},
                           {szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy},
                           {sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz}}};
    const std::array<double, 4> q = dominantEigenvector(nMatrix);

    StylusRegistration r;
    r.deviceToSpace.rotation = glm::normalize(glm::dquat(q[0], q[1], q[2], q[3]));
    r.deviceToSpace.scale = std::sqrt(spreadB / spreadA);
    r.deviceToSpace.translation = cb - r.deviceToSpace.scale * (r.deviceToSpace.rotation * ca);
    double sum = 0.0;
    for (std::size_t i = 0; i < device.size(); ++i) {
        const glm::dvec3 e = r.deviceToSpace.apply(device[i]) - space[i];
        sum += glm::dot(e, e);
    }
    r.rmsM = std::sqrt(sum / n);
    return r;
}

}  // namespace kizamu::xr
