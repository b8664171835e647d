/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file xrsim_control.h
 * @brief The control API of the simulated OpenXR runtime (libkizamu_xrsim.so): what the last
 * frame showed, what haptics were asked for, and events a user would cause on a headset.
 *
 * Tests link the library directly; the OpenXR loader's dlopen of the same file (through the
 * manifest KIZAMU_XRSIM_MANIFEST) gives the same copy, so these functions see the state the
 * application's OpenXR calls made. docs/XR-SIM.md describes the runtime and its capture files.
 *
 * Threading: every function takes the runtime's lock; callable from any thread, at any time
 * (before, during or after an instance's life). Errors: a non-zero int return, never an abort.
 * Units: times and durations in ns of the simulated clock (XrTime), frequencies in Hz.
 */
#ifndef KIZAMU_XRSIM_CONTROL_H
#define KIZAMU_XRSIM_CONTROL_H

#ifdef __cplusplus
extern "C" {
#endif

#define KIZAMU_XRSIM_EXPORT __attribute__((visibility("default")))

/** One haptic call: xrApplyHapticFeedback, or xrStopHapticFeedback (amplitude 0, duration 0). */
typedef struct KizamuXrSimHaptic {
    long long timeNs;     /**< the session's current XrTime (last predicted display time) */
    char hand[64];        /**< top-level path, "/user/hand/left" or "/user/hand/right" */
    float amplitude;      /**< 0..1 */
    long long durationNs; /**< XR_MIN_HAPTIC_DURATION (-1) as the application gave it */
    float frequencyHz;    /**< 0: XR_FREQUENCY_UNSPECIFIED */
} KizamuXrSimHaptic;

/**
 * The view last read back at xrEndFrame for `eye` (0 left, 1 right): RGBA8, top row first,
 * width*height*4 bytes, valid until the next xrEndFrame or kizamuXrSimReset.
 * @return 0 when a view exists; 1 when no projection layer was ended yet; 2 when eye is not 0/1.
 */
KIZAMU_XRSIM_EXPORT int kizamuXrSimLastView(int eye, int* width, int* height,
                                            const unsigned char** rgba);

/** xrEndFrame calls that succeeded, over all sessions, since load or kizamuXrSimReset. */
KIZAMU_XRSIM_EXPORT unsigned long long kizamuXrSimFramesEnded(void);

/** Haptic calls recorded since load or kizamuXrSimReset. */
KIZAMU_XRSIM_EXPORT int kizamuXrSimHapticCount(void);

/** Copies haptic call `i` (0 = oldest) to `out`. @return 0 ok; 1 when i is out of range. */
KIZAMU_XRSIM_EXPORT int kizamuXrSimHapticEvent(int i, KizamuXrSimHaptic* out);

/**
 * Runtime-initiated stop (the user quit from the headset): every running session goes down to
 * STOPPING (through VISIBLE and SYNCHRONIZED), and to EXITING after its xrEndSession.
 */
KIZAMU_XRSIM_EXPORT void kizamuXrSimRequestStop(void);

/**
 * Loses every session: state LOSS_PENDING is queued, and later calls on the session return
 * XR_ERROR_SESSION_LOST (xrDestroySession still works).
 */
KIZAMU_XRSIM_EXPORT void kizamuXrSimLoseSession(void);

/**
 * Sets the head pose in the LOCAL/STAGE frame: position in m, orientation as a unit quaternion
 * (x, y, z, w). Views and the VIEW space follow it. Default: origin, identity (looking down -Z).
 */
KIZAMU_XRSIM_EXPORT void kizamuXrSimSetHeadPose(const float position[3],
                                                const float orientation[4]);

/**
 * Forgets the recorded outputs (last views, frame count, haptics) and the head pose, for tests
 * that run one after another in one process. Live OpenXR handles are kept.
 */
KIZAMU_XRSIM_EXPORT void kizamuXrSimReset(void);

#ifdef __cplusplus
}
#endif

#endif
