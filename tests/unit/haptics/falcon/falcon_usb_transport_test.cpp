// SPDX-License-Identifier: Apache-2.0
/// @file falcon_usb_transport_test.cpp
/// @brief The libusb transport without a Falcon: opening fails with a clear message, not a crash.
#include "haptics/falcon/falcon_usb_transport.h"

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>
#include <string>

namespace {

using namespace kizamu::haptics::falcon;

TEST(FalconUsbTransport, OpeningWithoutAFalconIsAClearError) {
    std::unique_ptr<FalconUsbTransport> transport;
    try {
        transport = std::make_unique<FalconUsbTransport>();
    } catch (const std::runtime_error& e) {
        // No USB at all (a container without /dev/bus/usb): libusb itself cannot start.
        const std::string what = e.what();
        EXPECT_NE(what.find("libusb"), std::string::npos) << what;
        EXPECT_NE(what.find("0403:cb48"), std::string::npos) << what;
        return;
    }
    if (transport->count() > 0) GTEST_SKIP() << "a Falcon is plugged in; this test needs none";
    try {
        transport->open(0);
        FAIL() << "open() succeeded without a Falcon";
    } catch (const std::runtime_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("0403:cb48"), std::string::npos) << what;
        EXPECT_NE(what.find("no Falcon at index 0"), std::string::npos) << what;
    }
    EXPECT_FALSE(transport->isOpen());
    // A closed transport fails its I/O instead of touching a null handle.
    const std::array<uint8_t, 16> bytes{};
    std::array<uint8_t, 16> in{};
    EXPECT_FALSE(transport->write(bytes));
    EXPECT_EQ(transport->read(in, 1), -1);
    EXPECT_THROW(transport->setNormalMode(), std::runtime_error);
    transport->close();  // idempotent
}

}  // namespace
