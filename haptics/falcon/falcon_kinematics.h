// SPDX-License-Identifier: Apache-2.0
/// @file falcon_kinematics.h
/// @brief The Novint Falcon's delta-robot kinematics on the host: encoder counts to arm angles,
/// inverse and (iterative) forward kinematics, the angle Jacobian, and Cartesian force (N) to
/// the firmware's motor units.
///
/// Where it sits: FalconDevice's device thread turns each device packet's encoder counts into a
/// position (forwardKinematics, warm-started at the previous one) and each force the servo thread
/// wrote into motor units (jointTorques, then firmwareMotorUnits). Pure: no I/O, no allocation,
/// no state; every function is noexcept and safe on any thread. Units: SI (m, rad, N, N·m).
///
/// Frame ("kinematic frame", the one libnifalcon's kinematic model reports): origin on the
/// device's axis of symmetry inside the body, z along that axis towards the user (the grip
/// moves to larger z when pulled out: libnifalcon's cube test waits for z > 0.17 m after
/// "move the end effector all the way out"). FalconDevice's device frame is this
/// frame shifted by kWorkspaceCenter, so the device frame's origin is the workspace centre.
///
/// Model: the leg model of R. E. Stamper, "A three degree of freedom parallel manipulator with
/// only translational degrees of freedom" (PhD thesis, University of Maryland, 1997), with the
/// Falcon's dimensions as libnifalcon's FalconGeometry.h states them. Leg i sees the end
/// effector at q = Rz(-phi_i) p + (-r, -s, 0) = (u, v, w); its arm angle theta1 (the motor's
/// joint) satisfies
///   (u + c - a cos theta1)^2 + (w - a sin theta1)^2 = (d + e + b sin theta3)^2,
///   cos theta3 = (v + f) / b,
/// solved in closed form through t = tan(theta1 / 2) (the root libnifalcon's
/// FalconKinematicStamper::IK takes). The Jacobian d theta1 / dp is the exact implicit
/// derivative of that constraint (tests compare it with finite differences); libnifalcon's own
/// Jacobian agrees in its x and y columns.
///
/// Features:
///  [X] encoder -> angle, closed-form inverse kinematics, Newton forward kinematics (bounded)
///  [X] exact Jacobian; torque = J_p^T F with J_p = (d theta / dp)^-1; uniform torque scaling
///  [ ] gravity compensation of the grip, per-unit calibration of the 35 degree offset
/// Changes (breaking): 2026-12-06 first version.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <numbers>

namespace kizamu::haptics::falcon {

// ---- geometry (m), libnifalcon FalconGeometry.h, after Stamper's diagram (thesis p. 30) ----
inline constexpr double kArmA = 0.060;          ///< leg base to knee (the motor arm)
inline constexpr double kShinB = 0.1025;        ///< shin parallelogram side
inline constexpr double kEffectorC = 0.014;     ///< shin joint to effector centre, u component
inline constexpr double kJointD = 0.01125;      ///< shin to effector joint
inline constexpr double kJointE = 0.01125;      ///< knee to shin joint
inline constexpr double kEffectorF = -0.025;    ///< shin joint to effector centre, v component
inline constexpr double kBaseR = 0.037233758;   ///< frame origin to leg base, u component
inline constexpr double kBaseS = -0.027330909;  ///< frame origin to leg base, v component
/// Leg directions about z (rad): 90, -30 and -150 degrees, each turned by the 15 degree tilt
/// of the Falcon's axes from the desk plane (libnifalcon FalconGeometry.h, phy and OFFSET_ANGLE).
inline constexpr std::array<double, 3> kLegAngle{
    std::numbers::pi / 2 + std::numbers::pi / 12,
    -std::numbers::pi / 6 + std::numbers::pi / 12,
    -5 * std::numbers::pi / 6 + std::numbers::pi / 12,
};

// ---- encoders (libnifalcon FalconKinematic::getTheta and FalconGeometry.h) ----
inline constexpr double kWheelSlots = 320.0;       ///< slots on the encoder wheel; x4 quadrature
inline constexpr double kShaftDiameter = 0.01425;  ///< m, motor shaft (the capstan)
inline constexpr double kArmDrumDiameter = 0.110;  ///< m, the arm's drum the cable wraps
/// Arm angle per encoder count: one count is pi * shaft / (4 * slots) of cable, which turns the
/// drum by that length over its radius. About 0.0364 degrees.
inline constexpr double kRadPerCount =
    2.0 * std::numbers::pi * kShaftDiameter / (4.0 * kWheelSlots * kArmDrumDiameter);
/// Arm angle at encoder count 0 after homing (35 degrees, libnifalcon's THETA_OFFSET_ANGLE,
/// described there as approximate).
inline constexpr double kAngleAtZeroCount = 35.0 * std::numbers::pi / 180.0;

// ---- motor commands (libnifalcon FalconKinematicStamper::getForces) ----
/// Firmware units per N·m of arm torque; the firmware's sign is opposite to the torque's
/// (the published driver sends -10000 x torque).
inline constexpr double kUnitsPerNewtonMetre = -10000.0;
/// Largest arm torque sent (N·m): under the int16 full scale (32767 units = 3.28 N·m), so the
/// uniform scaling in firmwareMotorUnits, not integer clipping, is what limits a command.
inline constexpr double kMaxArmTorque = 3.0;

/// The workspace centre in the kinematic frame (m): the centre of the 6 cm test cube of
/// libnifalcon's falcon_test_cli (FalconCubeTest, corners z = 0.095 and 0.155).
inline const glm::dvec3 kWorkspaceCenter{0.0, 0.0, 0.125};

/// Arm angle (rad) of an encoder count. Complexity O(1). Threading: pure.
double encoderAngle(int16_t count) noexcept;
/// The three arm angles (rad) of three encoder counts.
glm::dvec3 encoderAngles(const std::array<int16_t, 3>& counts) noexcept;
/// The nearest encoder count of an arm angle (rad), clamped to int16 (emulators and tests).
int16_t angleToEncoder(double angle) noexcept;

/// Inverse kinematics: the three arm angles (rad) that put the end effector at `posKinematic`
/// (m). False (and `angles` unspecified) when a leg cannot reach it.
/// Complexity O(1). Threading: pure. Memory: none.
bool inverseKinematics(const glm::dvec3& posKinematic, glm::dvec3& angles) noexcept;

/// The angle Jacobian at `posKinematic`: row i is d theta_i / dp (rad/m). Indexing is glm's,
/// column first: dThetaDp[col][row]. False when a leg cannot reach the position or is singular
/// there (its arm angle does not depend on the position smoothly).
/// Complexity O(1). Threading: pure. Memory: none.
bool angleJacobian(const glm::dvec3& posKinematic, glm::dmat3& dThetaDp) noexcept;

/// Settings of the forward kinematics' Newton iteration.
struct ForwardSettings {
    int maxIterations = 20;       ///< bounded: the solve never takes longer than this many steps
    double toleranceRad = 1e-10;  ///< converged when every arm angle is this close (rad)
};

/// What forwardKinematics found.
struct ForwardResult {
    glm::dvec3 position{0.0};  ///< m, kinematic frame; the last iterate when not converged
    int iterations = 0;
    bool converged = false;
    double residualRad = 0.0;  ///< max |theta_i(position) - angles_i|
};

/// Forward kinematics: the end-effector position (m, kinematic frame) of three arm angles
/// (rad), by Newton's method on inverseKinematics with the exact Jacobian, halving a step that
/// leaves the reachable set or grows the residual. `guess` is where to start (the previous
/// position converges in 1-2 steps; kWorkspaceCenter works from anywhere in the workspace).
/// Complexity O(maxIterations) (each step O(1), at most 8 halvings). Threading: pure.
/// Memory: none.
ForwardResult forwardKinematics(const glm::dvec3& angles, const glm::dvec3& guess,
                                const ForwardSettings& settings = {}) noexcept;

/// The arm torques (N·m) that produce `force` (N, kinematic frame) at the end effector at
/// `posKinematic`: tau = J_p^T F with J_p = (d theta / dp)^-1 (virtual work: tau · dtheta =
/// F · dp). False (and `torque` zero) at an unreachable or singular position.
/// Complexity O(1). Threading: pure. Memory: none.
bool jointTorques(const glm::dvec3& posKinematic, const glm::dvec3& force,
                  glm::dvec3& torque) noexcept;

/// The firmware motor commands of three arm torques (N·m): scaled down together when one
/// exceeds `maxTorque` (so the force keeps its direction), times kUnitsPerNewtonMetre, rounded,
/// clamped to int16. Non-finite torques give zero commands.
/// Complexity O(1). Threading: pure. Memory: none.
std::array<int16_t, 3> firmwareMotorUnits(const glm::dvec3& torque,
                                          double maxTorque = kMaxArmTorque) noexcept;

}  // namespace kizamu::haptics::falcon
