// SPDX-License-Identifier: Apache-2.0
/// @file falcon_kinematics_test.cpp
/// @brief The Falcon's kinematics: the encoder scale, the home pose, inverse then forward over
/// the workspace, the Jacobian against finite differences, virtual work, and motor units.
#include "haptics/falcon/falcon_kinematics.h"

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace {

using namespace kizamu::haptics::falcon;

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(FalconKinematics, EncoderScale) {
    // 360 * 0.01425 / (4 * 320 * 0.110) degrees per count (libnifalcon's getTheta), worked by hand.
    EXPECT_NEAR(kRadPerCount / kDeg, 0.036434659, 1e-9);
    EXPECT_DOUBLE_EQ(encoderAngle(0), 35.0 * kDeg);
    EXPECT_NEAR(encoderAngle(1000) - encoderAngle(0), 1000 * kRadPerCount, 1e-15);
    EXPECT_EQ(angleToEncoder(encoderAngle(-1234)), -1234);
    EXPECT_EQ(angleToEncoder(1e9), 32767);
    EXPECT_EQ(angleToEncoder(std::nan("")), 0);
}

TEST(FalconKinematics, HomePoseLiesOnTheAxisAtTheClosedFormHeight) {
    // Encoders at 0 after homing: every arm at 35 degrees, so by symmetry the effector lies on
    // the z axis, where every leg sees (u, v, w) = (-r, -s, z) and the constraint gives
    // z = a sin t1 + sqrt(reach^2 - (c - r - a cos t1)^2), reach = d + e + b sin t3,
    // cos t3 = (f - s) / b: an independent closed form.
    const double t1 = 35.0 * kDeg;
    const double cosT3 = (kEffectorF - kBaseS) / kShinB;
    const double reach = kJointD + kJointE + kShinB * std::sqrt(1.0 - cosT3 * cosT3);
    const double du = kEffectorC - kBaseR - kArmA * std::cos(t1);
    const double zHome = kArmA * std::sin(t1) + std::sqrt(reach * reach - du * du);

    const ForwardResult fk = forwardKinematics(encoderAngles({0, 0, 0}), kWorkspaceCenter);
    ASSERT_TRUE(fk.converged);
    EXPECT_LE(fk.iterations, 8);
    EXPECT_NEAR(fk.position.x, 0.0, 1e-12);
    EXPECT_NEAR(fk.position.y, 0.0, 1e-12);
    EXPECT_NEAR(fk.position.z, zHome, 1e-10);
    // Within the 4 in workspace around its centre.
    EXPECT_NEAR(fk.position.z, kWorkspaceCenter.z, 0.0508);
    glm::dvec3 angles;
    ASSERT_TRUE(inverseKinematics(fk.position, angles));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(angles[i], t1, 1e-10);
}

TEST(FalconKinematics, ForwardInvertsInverseOverTheWorkspace) {
    int checked = 0;
    for (double x = -0.04; x <= 0.0401; x += 0.01) {
        for (double y = -0.04; y <= 0.0401; y += 0.01) {
            for (double z = -0.04; z <= 0.0401; z += 0.01) {
                const glm::dvec3 p = kWorkspaceCenter + glm::dvec3(x, y, z);
                glm::dvec3 angles;
                const bool reachable = inverseKinematics(p, angles);
                // A delta mechanism's reach is rounded, not a box: the ball of radius 4 cm about
                // the centre must be reachable; the cube's corners may not be.
                if (glm::length(glm::dvec3(x, y, z)) <= 0.0401) {
                    ASSERT_TRUE(reachable) << x << " " << y << " " << z;
                } else if (!reachable) {
                    continue;
                }
                const ForwardResult fk = forwardKinematics(angles, kWorkspaceCenter);
                ASSERT_TRUE(fk.converged)
                    << x << " " << y << " " << z << " residual " << fk.residualRad;
                EXPECT_LE(fk.iterations, 10);
                EXPECT_LT(glm::length(fk.position - p), 1e-9);
                // Warm-started one encoder count away, as on the device thread: a step or two.
                const ForwardResult warm = forwardKinematics(angles + glm::dvec3(kRadPerCount), p);
                EXPECT_TRUE(warm.converged);
                EXPECT_LE(warm.iterations, 3);
                ++checked;
            }
        }
    }
    EXPECT_GE(checked, 400);  // the 4 cm ball alone holds 257 of the 729 grid points
}

TEST(FalconKinematics, UnreachableInputsFailCleanly) {
    glm::dvec3 angles;
    EXPECT_FALSE(inverseKinematics({0.0, 0.0, 0.5}, angles));
    EXPECT_FALSE(inverseKinematics({std::nan(""), 0.0, 0.1}, angles));
    ForwardSettings settings;
    settings.maxIterations = 5;
    const ForwardResult fk = forwardKinematics({10.0, -10.0, 3.0}, kWorkspaceCenter, settings);
    EXPECT_FALSE(fk.converged);
    EXPECT_LE(fk.iterations, 5);
    glm::dvec3 torque{1.0};
    EXPECT_FALSE(jointTorques({0.0, 0.0, 0.5}, {1.0, 0.0, 0.0}, torque));
    EXPECT_EQ(torque, glm::dvec3(0.0));
}

TEST(FalconKinematics, JacobianMatchesFiniteDifferences) {
    std::mt19937 rng(32);
    std::uniform_real_distribution<double> offset(-0.04, 0.04);
    const double h = 1e-7;
    for (int n = 0; n < 200; ++n) {
        const glm::dvec3 p = kWorkspaceCenter + glm::dvec3(offset(rng), offset(rng), offset(rng));
        glm::dmat3 jac;
        ASSERT_TRUE(angleJacobian(p, jac));
        for (int col = 0; col < 3; ++col) {
            glm::dvec3 dp(0.0);
            dp[col] = h;
            glm::dvec3 plus, minus;
            ASSERT_TRUE(inverseKinematics(p + dp, plus));
            ASSERT_TRUE(inverseKinematics(p - dp, minus));
            const glm::dvec3 fd = (plus - minus) / (2.0 * h);
            for (int row = 0; row < 3; ++row) {
                EXPECT_NEAR(jac[col][row], fd[row], 1e-5 * std::max(1.0, std::abs(fd[row])))
                    << "row " << row << " col " << col << " seed case " << n;
            }
        }
    }
}

TEST(FalconKinematics, TorquesDoTheForcesVirtualWork) {
    // tau . dtheta = F . dp for a small joint motion, with dp from the forward kinematics.
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> offset(-0.035, 0.035), force(-9.0, 9.0),
        joint(-1.0, 1.0);
    for (int n = 0; n < 100; ++n) {
        const glm::dvec3 p = kWorkspaceCenter + glm::dvec3(offset(rng), offset(rng), offset(rng));
        const glm::dvec3 f(force(rng), force(rng), force(rng));
        glm::dvec3 tau;
        ASSERT_TRUE(jointTorques(p, f, tau));
        glm::dvec3 theta;
        ASSERT_TRUE(inverseKinematics(p, theta));
        const glm::dvec3 dTheta = 1e-6 * glm::dvec3(joint(rng), joint(rng), joint(rng));
        const ForwardResult plus = forwardKinematics(theta + dTheta, p);
        const ForwardResult minus = forwardKinematics(theta - dTheta, p);
        ASSERT_TRUE(plus.converged && minus.converged);
        const double workForce = glm::dot(f, (plus.position - minus.position) / 2.0);
        const double workTorque = glm::dot(tau, dTheta);
        EXPECT_NEAR(workTorque, workForce, 1e-6 * std::abs(workForce) + 1e-15) << "case " << n;
    }
}

TEST(FalconKinematics, FullForceAtTheCentreFitsTheTorqueLimit) {
    // Novint's 8.9 N along any axis at the workspace centre needs less than the torque cap,
    // so the uniform scaling only acts near the edges of the workspace.
    for (int axis = 0; axis < 3; ++axis) {
        glm::dvec3 f(0.0);
        f[axis] = 8.9;
        glm::dvec3 tau;
        ASSERT_TRUE(jointTorques(kWorkspaceCenter, f, tau));
        EXPECT_LT(std::max({std::abs(tau.x), std::abs(tau.y), std::abs(tau.z)}), kMaxArmTorque)
            << "axis " << axis;
    }
}

TEST(FalconKinematics, MotorUnitsScaleSignAndLimit) {
    // -10000 units per N·m (libnifalcon's getForces sign and scale).
    EXPECT_EQ(firmwareMotorUnits({0.1, -0.2, 0.0}), (std::array<int16_t, 3>{-1000, 2000, 0}));
    // Above the cap all three scale by the same factor: (6, 3, -1.5) with cap 3 -> (3, 1.5, -0.75).
    EXPECT_EQ(firmwareMotorUnits({6.0, 3.0, -1.5}, 3.0),
              (std::array<int16_t, 3>{-30000, -15000, 7500}));
    EXPECT_EQ(firmwareMotorUnits({std::nan(""), 0.1, 0.1}), (std::array<int16_t, 3>{0, 0, 0}));
    EXPECT_EQ(firmwareMotorUnits({INFINITY, 0.1, 0.1}), (std::array<int16_t, 3>{0, 0, 0}));
    // A cap above the int16 range clamps instead of wrapping.
    EXPECT_EQ(firmwareMotorUnits({-10.0, 10.0, 0.0}, 100.0),
              (std::array<int16_t, 3>{32767, -32768, 0}));
}

}  // namespace
