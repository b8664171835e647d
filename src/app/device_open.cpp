// SPDX-License-Identifier: Apache-2.0
/// @file device_open.cpp
/// @brief openDevice: the simulated stylus, a Falcon over libusb, a HID PID device over hidraw.
#include "app/device_open.h"

#include "haptics/falcon/falcon_device.h"
#include "haptics/falcon/falcon_usb_transport.h"
#include "haptics/hid/device_list.h"
#include "haptics/hid/hidapi_transport.h"
#include "haptics/servo_loop.h"

#include <stdexcept>

namespace kizamu::app {

namespace {

using haptics::hid::FoundKind;

[[noreturn]] void fail(const std::string& name, const std::string& why) {
    throw std::runtime_error("--device " + name + ": " + why);
}

/// The first listed device of `kind` whose id is `id` (empty: any), or nothing.
std::optional<haptics::hid::FoundDevice> find(const haptics::hid::DeviceListing& l, FoundKind kind, const std::string& id,
                                              unsigned* index = nullptr) {
    unsigned n = 0;
    for (const haptics::hid::FoundDevice& d : l.devices) {
        if (d.kind != kind) continue;
        if (id.empty() || d.id == id) {
            if (index) *index = n;
            return d;
        }
        ++n;
    }
    return std::nullopt;
}

OpenedDevice openSim(const std::string& name, const DeviceOpenOptions& o, bool wallClock) {
    OpenedDevice out;
    out.id = "sim";
    if (o.liveHand) {
        if (!wallClock) fail(name, "a live hand needs the wall clock");
        sim::Hand rest;
        rest.add(0.0, o.liveStart);
        out.stylus = std::make_unique<sim::SimulatedStylus>(rest);
    } else if (o.hand) {
        out.stylus = std::make_unique<sim::SimulatedStylus>(*o.hand);
    } else {
        fail(name, "the simulated stylus needs a hand: --hand FILE (docs/HAND.md)");
    }
    if (wallClock) {
        out.realtime = std::make_unique<sim::RealtimeStylus>(*out.stylus, &haptics::ServoLoop::clockNs);
        if (o.liveHand) out.realtime->setLiveHand(o.liveHand);
    }
    return out;
}

OpenedDevice openFalcon(const std::string& name, const std::string& which, const DeviceOpenOptions& o) {
    unsigned index = 0;
    if (!which.empty()) {
        const haptics::hid::DeviceListing l = haptics::hid::listDevices({true, false});
        if (!find(l, FoundKind::Falcon, which, &index)) fail(name, "no such Falcon (kizamu devices lists them)");
    }
    OpenedDevice out;
    out.id = which.empty() ? "falcon" : which;
    try {
        auto transport = std::make_unique<haptics::falcon::FalconUsbTransport>();
        transport->open(index);
        out.hardware = std::make_unique<haptics::falcon::FalconDevice>(std::move(transport), o.firmware);
    } catch (const std::exception& e) {
        fail(name, e.what());
    }
    return out;
}

OpenedDevice openHid(const std::string& name, std::string path) {
    if (path.empty()) {
        const haptics::hid::DeviceListing l = haptics::hid::listDevices({false, true});
        const auto d = find(l, FoundKind::HidPid, "");
        if (!d) fail(name, "no HID force-feedback device found (kizamu devices says why)");
        if (!d->available) fail(name, d->id + ": " + d->status);
        path = d->id;
    }
    OpenedDevice out;
    out.id = path;
    out.planar = true;
    try {
        auto device = haptics::hid::openHidPidDevice(path);
        device->start();
        out.hardware = std::move(device);
    } catch (const std::exception& e) {
        fail(name, e.what());
    }
    return out;
}

}  // namespace

haptics::Device& OpenedDevice::device() const {
    if (hardware) return *hardware;
    if (realtime) return *realtime;
    return *stylus;
}

OpenedDevice openDevice(const std::string& name, const DeviceOpenOptions& options, bool wallClock) {
    if (name == "sim") return openSim(name, options, wallClock);
    if (name == "falcon" || name.rfind("falcon:", 0) == 0) {
        if (!wallClock) fail(name, "a real device runs in real time (--rate > 0)");
        return openFalcon(name, name == "falcon" ? std::string() : name, options);
    }
    if (name == "hid" || name.rfind("hid:", 0) == 0) {
        if (!wallClock) fail(name, "a real device runs in real time (--rate > 0)");
        return openHid(name, name == "hid" ? std::string() : name.substr(4));
    }
    if (name == "auto") {
        if (wallClock) {
            const haptics::hid::DeviceListing l = haptics::hid::listDevices();
            for (const haptics::hid::FoundDevice& d : l.devices) {
                if (!d.available || d.kind == FoundKind::Simulated) continue;
                return d.kind == FoundKind::Falcon ? openFalcon(name, d.id, options) : openHid(name, d.id);
            }
        }
        return openSim(name, options, wallClock);
    }
    fail(name, "unknown device (sim, falcon[:BUS:ADDR], hid[:/dev/hidrawN] or auto)");
}

}  // namespace kizamu::app
