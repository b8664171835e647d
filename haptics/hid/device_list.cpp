// SPDX-License-Identifier: Apache-2.0
/// @file device_list.cpp
/// @brief Enumeration of Falcons (libusb) and HID PID devices (hidapi), plus the simulated
/// stylus (sources: the header).
#include "haptics/hid/device_list.h"

#include "haptics/hid/device_table.h"
#include "haptics/hid/hid_report_descriptor.h"
#include "haptics/hid/hidapi_transport.h"

#include <hidapi.h>
#include <libusb.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>

namespace kizamu::haptics::hid {

namespace {

constexpr const char* kRulesHint =
    "install the udev rules docs/udev/70-kizamu-haptics.rules (see docs/DEVICES.md), then re-plug the device";

FoundDevice simulatedStylus() {
    FoundDevice d;
    d.kind = FoundKind::Simulated;
    d.id = "sim";
    d.name = "simulated stylus (sim/simulated_stylus.h)";
    d.available = true;
    d.status = "ok";
    d.axes = 3;
    d.maxForce = 9.0;  // StylusSettings::maxForce's default
    return d;
}

void listFalcons(DeviceListing& out) {
    libusb_context* ctx = nullptr;
    if (const int rc = libusb_init(&ctx); rc != 0) {
        out.notes.push_back(std::string("libusb unavailable (") + libusb_error_name(rc) +
                            "): Novint Falcons were not looked for");
        return;
    }
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &list);
    if (n < 0) {
        out.notes.push_back(std::string("libusb could not list USB devices (") + libusb_error_name(int(n)) +
                            "): Novint Falcons were not looked for");
        libusb_exit(ctx);
        return;
    }
    for (ssize_t i = 0; i < n; ++i) {
        libusb_device_descriptor desc{};
        if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
        if (desc.idVendor != kFalconVendorId || desc.idProduct != kFalconProductId) continue;
        FoundDevice d;
        d.kind = FoundKind::Falcon;
        char id[64];
        std::snprintf(id, sizeof id, "falcon:%03u:%03u", unsigned(libusb_get_bus_number(list[i])),
                      unsigned(libusb_get_device_address(list[i])));
        d.id = id;
        d.name = "Novint Falcon";
        d.vendorId = desc.idVendor;
        d.productId = desc.idProduct;
        d.axes = 3;
        d.maxForce = 8.9;  // Novint's published 2 lbf
        libusb_device_handle* h = nullptr;
        const int rc = libusb_open(list[i], &h);
        if (rc == 0) {
            libusb_close(h);
            d.available = true;
            d.status = "ok (its firmware must be supplied with --firmware FILE)";
        } else if (rc == LIBUSB_ERROR_ACCESS) {
            d.status = std::string("permission denied opening the USB device: ") + kRulesHint;
        } else {
            d.status = std::string("cannot open: ") + libusb_error_name(rc);
        }
        out.devices.push_back(std::move(d));
    }
    libusb_free_device_list(list, 1);
    libusb_exit(ctx);
}

/// Whether the descriptor of `path` (sysfs) has PID usages; sets `axes` from its layout.
bool descriptorSaysPid(const std::string& path, int& axes, std::string& why) {
    try {
        const HidReportDescriptor d = parseReportDescriptor(readSysfsReportDescriptor(path));
        if (!d.hasPidUsages()) return false;
        try {
            axes = int(std::min<std::size_t>(findPidLayout(d).axisCount, 2));
        } catch (const std::exception& e) {
            why = e.what();
        }
        return true;
    } catch (const std::exception& e) {
        why = e.what();
        return false;
    }
}

void listHid(DeviceListing& out) {
    if (!ensureHidapi()) {
        out.notes.push_back("hidapi unavailable (hid_init failed): HID force-feedback devices were not looked for");
        return;
    }
    hid_device_info* all = hid_enumerate(0, 0);
    if (all == nullptr && access("/sys/class/hidraw", R_OK) != 0)
        out.notes.push_back("no /sys/class/hidraw on this machine: HID devices cannot be listed (Linux hidraw only)");
    std::vector<std::string> seen;
    for (const hid_device_info* h = all; h != nullptr; h = h->next) {
        if (h->path == nullptr) continue;
        const std::string path = h->path;
        // hidraw reports one entry per top-level collection, all on the same node.
        if (std::find(seen.begin(), seen.end(), path) != seen.end()) continue;
        const KnownDevice* known = findKnownDevice(h->vendor_id, h->product_id);
        int axes = known != nullptr ? known->axes : 0;
        std::string why;
        bool pid = known != nullptr || isPidUsagePage(h->usage_page);
        // Readable descriptors decide the axis count, and catch PID collections nested inside a
        // Joystick collection (whose top-level page is Generic Desktop).
        const bool fromDescriptor = descriptorSaysPid(path, axes, why);
        pid = pid || fromDescriptor;
        if (!pid) continue;
        seen.push_back(path);
        FoundDevice d;
        d.kind = FoundKind::HidPid;
        d.id = path;
        d.vendorId = h->vendor_id;
        d.productId = h->product_id;
        if (known != nullptr) {
            d.name = known->name;
        } else {
            char name[160];
            std::snprintf(name, sizeof name, "%ls %ls", h->manufacturer_string ? h->manufacturer_string : L"",
                          h->product_string ? h->product_string : L"HID force-feedback device");
            d.name = name;
        }
        d.axes = axes;
        d.maxForce = known != nullptr ? known->maxForce : kGenericPidMaxForce;
        if (access(path.c_str(), R_OK | W_OK) == 0) {
            d.available = true;
            d.status = "ok";
        } else {
            d.status = "no read/write access to " + path + ": " + kRulesHint;
        }
        if (!why.empty() && d.axes == 0) d.status += " (descriptor: " + why + ")";
        out.devices.push_back(std::move(d));
    }
    hid_free_enumeration(all);
}

}  // namespace

bool DeviceListing::anyReal() const noexcept {
    return std::any_of(devices.begin(), devices.end(),
                       [](const FoundDevice& d) { return d.kind != FoundKind::Simulated; });
}

DeviceListing listDevices(const ListOptions& options) {
    DeviceListing out;
    out.devices.push_back(simulatedStylus());
    if (options.usb) listFalcons(out);
    if (options.hid) listHid(out);
    return out;
}

}  // namespace kizamu::haptics::hid
