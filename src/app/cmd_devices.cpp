// SPDX-License-Identifier: Apache-2.0
/// @file cmd_devices.cpp
/// @brief `kizamu devices [--json]`: the haptic devices this machine has (Novint Falcons, HID
/// force-feedback devices) and the simulated stylus, which is always available.
///
/// The enumeration is haptics/hid/device_list.h; this file only prints. Exit code 0 whether or
/// not a real device is found: finding none is an answer, not an error.
#include "app/commands.h"
#include "haptics/hid/device_list.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>

namespace kizamu::app {

namespace {

using haptics::hid::DeviceListing;
using haptics::hid::FoundDevice;
using haptics::hid::FoundKind;

const char* kindName(FoundKind k) {
    switch (k) {
        case FoundKind::Simulated: return "sim";
        case FoundKind::Falcon: return "falcon";
        case FoundKind::HidPid: return "hid-pid";
    }
    return "unknown";
}

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

void printJson(const DeviceListing& l) {
    std::printf("{\n  \"devices\": [\n");
    for (std::size_t i = 0; i < l.devices.size(); ++i) {
        const FoundDevice& d = l.devices[i];
        std::printf("    {\"id\": %s, \"kind\": \"%s\", \"name\": %s, \"vendor_id\": \"%04x\", \"product_id\": \"%04x\", "
                    "\"available\": %s, \"status\": %s, \"axes\": %d, \"max_force_n\": %g}%s\n",
                    jsonString(d.id).c_str(), kindName(d.kind), jsonString(d.name).c_str(), unsigned(d.vendorId),
                    unsigned(d.productId), d.available ? "true" : "false", jsonString(d.status).c_str(), d.axes,
                    d.maxForce, i + 1 < l.devices.size() ? "," : "");
    }
    std::printf("  ],\n  \"notes\": [");
    for (std::size_t i = 0; i < l.notes.size(); ++i)
        std::printf("%s%s", i ? ", " : "", jsonString(l.notes[i]).c_str());
    std::printf("],\n  \"real_devices\": %s\n}\n", l.anyReal() ? "true" : "false");
}

void printText(const DeviceListing& l) {
    std::printf("Haptic devices:\n");
    for (const FoundDevice& d : l.devices) {
        std::printf("  %-22s %-8s %s", d.id.c_str(), kindName(d.kind), d.name.c_str());
        if (d.kind != FoundKind::Simulated) std::printf(" [%04x:%04x]", unsigned(d.vendorId), unsigned(d.productId));
        std::printf("\n");
        std::printf("  %-22s          %s; ", "", d.available ? "available" : "NOT available");
        if (d.axes > 0)
            std::printf("%d axes, ", d.axes);
        else
            std::printf("axes unknown, ");
        std::printf("max force %.3g N\n", d.maxForce);
        if (d.status != "ok") std::printf("  %-22s          %s\n", "", d.status.c_str());
    }
    for (const std::string& n : l.notes) std::printf("note: %s\n", n.c_str());
    if (!l.anyReal()) {
        std::printf("\nNo real haptic device found; only the simulated stylus (sim) is available.\n"
                    "If one is connected, it may be that:\n"
                    "  - it is not plugged in, or not powered (a Falcon needs its power supply);\n"
                    "  - this user may not open it: install docs/udev/70-kizamu-haptics.rules "
                    "(docs/DEVICES.md) and re-plug it;\n"
                    "  - HID devices are not reachable through /dev/hidraw* here (a container or VM "
                    "without USB or hidraw passthrough).\n");
    }
}

}  // namespace

void addDevicesCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand("devices", "List the haptic devices found (Novint Falcon, HID force-feedback) "
                                              "and the simulated stylus");
    auto json = std::make_shared<bool>(false);
    cmd->add_flag("--json", *json, "Print a machine-readable list");
    cmd->callback([json] {
        const DeviceListing l = haptics::hid::listDevices();
        if (*json)
            printJson(l);
        else
            printText(l);
    });
}

}  // namespace kizamu::app
