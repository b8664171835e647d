// SPDX-License-Identifier: Apache-2.0
/// @file device_open.h
/// @brief Which haptic device drives the tool: a name on the command line (`--device sim |
/// falcon[:BUS:ADDR] | hid[:/dev/hidrawN] | auto`) opened as a haptics::Device, with what the
/// servo loop needs to know about it (is it planar, is it on the wall clock already).
///
/// `auto` takes the first real device `kizamu devices` lists as available, else the simulated
/// stylus. The simulated stylus needs a hand: a script (`--hand FILE`) or a live one (the mouse,
/// sim/live_hand.h). Real devices run on the wall clock only. Cold path; errors are one line.
#pragma once

#include "haptics/device.h"
#include "sim/hand.h"
#include "sim/live_hand.h"
#include "sim/realtime_stylus.h"
#include "sim/simulated_stylus.h"

#include <memory>
#include <optional>
#include <string>

namespace kizamu::app {

struct DeviceOpenOptions {
    std::string firmware;          ///< the Falcon's firmware file (Novint's; we cannot ship it)
    std::optional<sim::Hand> hand;  ///< sim: a scripted hand
    sim::LiveHand* liveHand = nullptr;  ///< sim: a live hand instead (the mouse), on the wall clock
    glm::dvec3 liveStart{0.0};          ///< m, device frame: where the stylus rests before the live hand moves it
};

/// An open device. For the simulated stylus both `stylus` and (on the wall clock) `realtime`
/// are set and `device` is one of them.
struct OpenedDevice {
    std::string id;                                   ///< what was opened ("sim", "falcon", "/dev/hidraw3")
    std::unique_ptr<sim::SimulatedStylus> stylus;     ///< sim only
    std::unique_ptr<sim::RealtimeStylus> realtime;    ///< sim on the wall clock
    std::unique_ptr<haptics::Device> hardware;        ///< a real device
    bool planar = false;                              ///< one or two axes: the tool is projected onto the clay
    haptics::Device& device() const;
};

/// Opens `name` (see the file comment). `wallClock`: for the simulated stylus, wrap it in a
/// RealtimeStylus (the real-time servo loop); real devices are always on the wall clock.
/// @throw std::runtime_error "--device NAME: why" (no such device, permissions, no firmware,
///        no hand for the simulated stylus)
OpenedDevice openDevice(const std::string& name, const DeviceOpenOptions& options, bool wallClock);

}  // namespace kizamu::app
