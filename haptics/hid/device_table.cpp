// SPDX-License-Identifier: Apache-2.0
/// @file device_table.cpp
/// @brief The known HID force-feedback devices (sources: the header).
#include "haptics/hid/device_table.h"

#include <array>

namespace kizamu::haptics::hid {

namespace {

constexpr std::array<KnownDevice, 1> kDevices{{
    {0x1209, 0xFFB0, "OpenFFBoard", 1, 0.0, 5.0,
     "no published torque (motor dependent); 5 N is a conservative figure chosen by Kizamu"},
}};

}  // namespace

std::span<const KnownDevice> knownDevices() noexcept { return kDevices; }

const KnownDevice* findKnownDevice(uint16_t vendorId, uint16_t productId) noexcept {
    for (const KnownDevice& d : kDevices)
        if (d.vendorId == vendorId && d.productId == productId) return &d;
    return nullptr;
}

}  // namespace kizamu::haptics::hid
