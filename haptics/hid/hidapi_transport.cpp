// SPDX-License-Identifier: Apache-2.0
/// @file hidapi_transport.cpp
/// @brief hidapi (hidraw) transport and the sysfs report descriptor (sources: the header).
#include "haptics/hid/hidapi_transport.h"

#include "haptics/hid/device_table.h"

#include <hidapi.h>

#include <unistd.h>

#include <fstream>
#include <iterator>
#include <mutex>

namespace kizamu::haptics::hid {

bool ensureHidapi() noexcept {
    static std::once_flag once;
    static bool ok = false;
    std::call_once(once, [] { ok = hid_init() == 0; });
    return ok;
}

std::unique_ptr<HidapiTransport> HidapiTransport::open(const std::string& path) {
    if (!ensureHidapi()) throw HidDeviceError("hidapi: hid_init failed");
    hid_device* d = hid_open_path(path.c_str());
    if (d == nullptr) {
        std::string why = "cannot open " + path;
        if (::access(path.c_str(), R_OK | W_OK) != 0)
            why += ": no read/write access (install the udev rules in docs/udev/, see docs/DEVICES.md)";
        throw HidDeviceError(why);
    }
    return std::unique_ptr<HidapiTransport>(new HidapiTransport(d));
}

HidapiTransport::~HidapiTransport() {
    if (mDevice != nullptr) hid_close(mDevice);
}

bool HidapiTransport::writeReport(std::span<const uint8_t> report) {
    return hid_write(mDevice, report.data(), report.size()) >= 0;
}

int HidapiTransport::readReport(std::span<uint8_t> buffer, int timeoutMs) {
    return hid_read_timeout(mDevice, buffer.data(), buffer.size(), timeoutMs);
}

bool HidapiTransport::sendFeature(std::span<const uint8_t> report) {
    return hid_send_feature_report(mDevice, report.data(), report.size()) >= 0;
}

int HidapiTransport::getFeature(std::span<uint8_t> buffer) {
    return hid_get_feature_report(mDevice, buffer.data(), buffer.size());
}

bool HidapiTransport::ids(uint16_t& vendorId, uint16_t& productId) const {
    // hid_get_device_info is part of hidapi's API from 0.13.
    const hid_device_info* info = hid_get_device_info(mDevice);
    if (info == nullptr) return false;
    vendorId = info->vendor_id;
    productId = info->product_id;
    return true;
}

std::vector<uint8_t> readSysfsReportDescriptor(const std::string& devicePath) {
    const auto slash = devicePath.find_last_of('/');
    const std::string node = slash == std::string::npos ? devicePath : devicePath.substr(slash + 1);
    const std::string sysfs = "/sys/class/hidraw/" + node + "/device/report_descriptor";
    std::ifstream f(sysfs, std::ios::binary);
    if (!f) throw HidDeviceError("cannot read the report descriptor " + sysfs);
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (bytes.empty()) throw HidDeviceError("empty report descriptor " + sysfs);
    return bytes;
}

std::unique_ptr<HidPidDevice> openHidPidDevice(const std::string& devicePath, HidPidSettings settings, bool useTable) {
    const PidLayout layout = findPidLayout(parseReportDescriptor(readSysfsReportDescriptor(devicePath)));
    auto transport = HidapiTransport::open(devicePath);
    uint16_t vendorId = 0, productId = 0;
    if (useTable && transport->ids(vendorId, productId))
        if (const KnownDevice* k = findKnownDevice(vendorId, productId)) {
            settings.name = k->name;
            settings.maxForce = k->maxForce;
        }
    return std::make_unique<HidPidDevice>(std::move(transport), layout, settings);
}

}  // namespace kizamu::haptics::hid
