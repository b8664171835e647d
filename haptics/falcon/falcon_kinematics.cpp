// SPDX-License-Identifier: Apache-2.0
/// @file falcon_kinematics.cpp
/// @brief The leg model, its closed-form inverse, the exact Jacobian and the Newton forward
/// solve (model and sources in falcon_kinematics.h).
#include "haptics/falcon/falcon_kinematics.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace kizamu::haptics::falcon {

namespace {

/// sin theta3 below this: the shin is (nearly) parallel to the v axis, where theta1 stops
/// depending smoothly on v; such positions lie outside the mechanism's range of motion.
constexpr double kMinSinTheta3 = 1e-6;
/// |d g / d theta1| below this (m^2): the arm is at a turning point of its constraint.
constexpr double kMinConstraintSlope = 1e-12;
/// |det| of the angle Jacobian below this (rad^3/m^3): singular for the torque solve.
constexpr double kMinDeterminant = 1e-9;
constexpr int kMaxHalvings = 8;

/// One leg's view of the end effector: the leg frame coordinates and the angles it implies.
struct Leg {
    double u = 0.0, v = 0.0, w = 0.0;
    double theta1 = 0.0;  ///< arm angle (rad)
    double sinTheta3 = 0.0;
    double reach = 0.0;  ///< d + e + b sin theta3 (m): the knee-to-effector span
};

/// The leg frame coordinates of `p` for leg `i`: q = Rz(-phi_i) p + (-r, -s, 0).
Leg legCoordinates(const glm::dvec3& p, int i) noexcept {
    const double cp = std::cos(kLegAngle[i]), sp = std::sin(kLegAngle[i]);
    Leg leg;
    leg.u = cp * p.x + sp * p.y - kBaseR;
    leg.v = -sp * p.x + cp * p.y - kBaseS;
    leg.w = p.z;
    return leg;
}

/// Solves leg `i` for its arm angle; false when the leg cannot reach `p`.
bool solveLeg(const glm::dvec3& p, int i, Leg& leg) noexcept {
    leg = legCoordinates(p, i);
    const double cosTheta3 = (leg.v + kEffectorF) / kShinB;
    if (!(std::abs(cosTheta3) < 1.0)) return false;  // also rejects NaN
    leg.sinTheta3 = std::sqrt(1.0 - cosTheta3 * cosTheta3);
    if (leg.sinTheta3 < kMinSinTheta3) return false;
    leg.reach = kJointD + kJointE + kShinB * leg.sinTheta3;
    // (u + c - a cos t1)^2 + (w - a sin t1)^2 = reach^2 with t = tan(t1 / 2) becomes
    // q2 t^2 + q1 t + q0 = 0, where k = (u + c)^2 + w^2 + a^2 - reach^2.
    const double uc = leg.u + kEffectorC;
    const double k = uc * uc + leg.w * leg.w + kArmA * kArmA - leg.reach * leg.reach;
    const double q0 = k - 2.0 * kArmA * uc;
    const double q1 = -4.0 * kArmA * leg.w;
    const double q2 = k + 2.0 * kArmA * uc;
    const double disc = q1 * q1 - 4.0 * q0 * q2;
    if (!(disc >= 0.0)) return false;
    double t = 0.0;
    if (std::abs(q2) > 1e-15) {
        t = (-q1 - std::sqrt(disc)) / (2.0 * q2);  // the assembly mode of the Falcon's legs
    } else if (std::abs(q1) > 1e-15) {
        t = -q0 / q1;
    } else {
        return false;
    }
    leg.theta1 = 2.0 * std::atan(t);
    return std::isfinite(leg.theta1);
}

/// Row i of the angle Jacobian: d theta1 / dp for a solved leg. From the constraint
/// g(u, v, w, theta1) = 0: d theta1 / dq = -(dg/dq) / (dg/dtheta1), then dq/dp = Rz(-phi_i).
bool legGradient(const Leg& leg, int i, glm::dvec3& row) noexcept {
    const double s1 = std::sin(leg.theta1), c1 = std::cos(leg.theta1);
    const double uc = leg.u + kEffectorC;
    // dg/dtheta1 = 2a ((u + c) sin t1 - w cos t1)
    const double gTheta = 2.0 * kArmA * (uc * s1 - leg.w * c1);
    if (!(std::abs(gTheta) > kMinConstraintSlope)) return false;
    const double gu = 2.0 * (uc - kArmA * c1);
    const double gw = 2.0 * (leg.w - kArmA * s1);
    // d(b sin t3)/dv = -(v + f) / (b sin t3), and g has -reach^2
    const double gv = 2.0 * leg.reach * (leg.v + kEffectorF) / (kShinB * leg.sinTheta3);
    const double du = -gu / gTheta, dv = -gv / gTheta, dw = -gw / gTheta;
    const double cp = std::cos(kLegAngle[i]), sp = std::sin(kLegAngle[i]);
    row = glm::dvec3(du * cp - dv * sp, du * sp + dv * cp, dw);
    return std::isfinite(row.x) && std::isfinite(row.y) && std::isfinite(row.z);
}

double maxAbs(const glm::dvec3& v) noexcept {
    return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

}  // namespace

double encoderAngle(int16_t count) noexcept {
    return kAngleAtZeroCount + kRadPerCount * double(count);
}

glm::dvec3 encoderAngles(const std::array<int16_t, 3>& counts) noexcept {
    return {encoderAngle(counts[0]), encoderAngle(counts[1]), encoderAngle(counts[2])};
}

int16_t angleToEncoder(double angle) noexcept {
    if (!std::isfinite(angle)) return 0;
    const double count = std::round((angle - kAngleAtZeroCount) / kRadPerCount);
    return static_cast<int16_t>(std::clamp(count, double(std::numeric_limits<int16_t>::min()),
                                           double(std::numeric_limits<int16_t>::max())));
}

bool inverseKinematics(const glm::dvec3& posKinematic, glm::dvec3& angles) noexcept {
    for (int i = 0; i < 3; ++i) {
        Leg leg;
        if (!solveLeg(posKinematic, i, leg)) return false;
        angles[i] = leg.theta1;
    }
    return true;
}

bool angleJacobian(const glm::dvec3& posKinematic, glm::dmat3& dThetaDp) noexcept {
    for (int i = 0; i < 3; ++i) {
        Leg leg;
        glm::dvec3 row;
        if (!solveLeg(posKinematic, i, leg) || !legGradient(leg, i, row)) return false;
        for (int col = 0; col < 3; ++col) dThetaDp[col][i] = row[col];
    }
    return true;
}

ForwardResult forwardKinematics(const glm::dvec3& angles, const glm::dvec3& guess,
                                const ForwardSettings& settings) noexcept {
    ForwardResult result;
    glm::dvec3 p = guess;
    glm::dvec3 theta;
    if (!inverseKinematics(p, theta)) {
        p = kWorkspaceCenter;
        if (!inverseKinematics(p, theta)) return result;
    }
    double residual = maxAbs(angles - theta);
    for (int it = 0; it < settings.maxIterations && !(residual < settings.toleranceRad); ++it) {
        glm::dmat3 jac;
        if (!angleJacobian(p, jac) || std::abs(glm::determinant(jac)) < kMinDeterminant) break;
        const glm::dvec3 step = glm::inverse(jac) * (angles - theta);
        double scale = 1.0;
        bool moved = false;
        for (int h = 0; h <= kMaxHalvings; ++h, scale *= 0.5) {
            const glm::dvec3 candidate = p + scale * step;
            glm::dvec3 candidateTheta;
            if (!inverseKinematics(candidate, candidateTheta)) continue;
            const double candidateResidual = maxAbs(angles - candidateTheta);
            if (candidateResidual < residual) {
                p = candidate;
                theta = candidateTheta;
                residual = candidateResidual;
                moved = true;
                break;
            }
        }
        result.iterations = it + 1;
        if (!moved) break;
    }
    result.position = p;
    result.residualRad = residual;
    result.converged = residual < settings.toleranceRad;
    return result;
}

bool jointTorques(const glm::dvec3& posKinematic, const glm::dvec3& force,
                  glm::dvec3& torque) noexcept {
    torque = glm::dvec3(0.0);
    glm::dmat3 jac;
    if (!angleJacobian(posKinematic, jac) || std::abs(glm::determinant(jac)) < kMinDeterminant)
        return false;
    // tau = J_p^T F = (d theta / dp)^-T F
    const glm::dvec3 tau = glm::transpose(glm::inverse(jac)) * force;
    if (!(std::isfinite(tau.x) && std::isfinite(tau.y) && std::isfinite(tau.z))) return false;
    torque = tau;
    return true;
}

std::array<int16_t, 3> firmwareMotorUnits(const glm::dvec3& torque, double maxTorque) noexcept {
    std::array<int16_t, 3> units{0, 0, 0};
    if (!(std::isfinite(torque.x) && std::isfinite(torque.y) && std::isfinite(torque.z)))
        return units;
    if (!(maxTorque > 0.0)) return units;
    const double largest = maxAbs(torque);
    const double scale = largest > maxTorque ? maxTorque / largest : 1.0;
    for (int i = 0; i < 3; ++i) {
        const double value = std::round(kUnitsPerNewtonMetre * scale * torque[i]);
        units[i] =
            static_cast<int16_t>(std::clamp(value, double(std::numeric_limits<int16_t>::min()),
                                            double(std::numeric_limits<int16_t>::max())));
    }
    return units;
}

}  // namespace kizamu::haptics::falcon
