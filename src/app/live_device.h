// SPDX-License-Identifier: Apache-2.0
/// @file live_device.h
/// @brief `kizamu live --device NAME`: the servo thread, a haptic device and the live engine
/// together, headless; the servo ticks traced and the samples recorded on request. The
/// simulated stylus follows a hand file (lock step or real time); a real device (a Falcon, a
/// HID force-feedback device) is held by a person for `seconds`.
#pragma once

#include <string>

namespace kizamu::app {

struct DeviceLiveOptions {
    std::string device = "sim";  ///< app/device_open.h: sim, falcon[:BUS:ADDR], hid[:PATH], auto
    std::string hand;            ///< hand file (docs/HAND.md), for the simulated stylus
    std::string firmware;        ///< the Falcon's firmware file
    double seconds = 0.0;        ///< s a real device runs; 0: 10 s (the simulated stylus: its hand's script)
    double rate = 1000.0;        ///< Hz; 0: lock step at 1 kHz on a virtual clock, deterministic
    std::string record;          ///< the servo trace (docs/HAPTIC-TRACE.md); empty: none
    std::string recordTrajectory;  ///< the tool samples as a trajectory (docs/TRAJECTORY.md); empty: none
    std::string session, out, units;
    int level = 0;                 ///< finest level of the start clay (0: 9)
    unsigned threads = 0;
    double toolRadius = 0.003;     ///< m, the carving sphere the stylus holds
    double stiffness = 0.0;        ///< N/m asked for in the world (0: the stiffest passive)
    double forceScale = 1.0;
};

/// Runs it and prints what happened (ticks, contact, forces, strokes, the servo loop's timing in
/// real time). @throw kizamu::FileError, std::runtime_error with a one-line message.
void runDeviceLive(const DeviceLiveOptions& o);

}  // namespace kizamu::app
