// SPDX-License-Identifier: Apache-2.0
/// @file capture.cpp
/// @brief events.jsonl and the view PNGs of $KIZAMU_XRSIM_CAPTURE.
#include "sim/openxr/capture.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_image_write.h>

#include <cstdio>

namespace kizamu::xrsim {

void captureEvent(const Runtime& rt, const std::string& jsonLine) {
    if (rt.captureDir.empty()) return;
    std::FILE* f = std::fopen((rt.captureDir + "/events.jsonl").c_str(), "a");
    if (f == nullptr) return;
    std::fprintf(f, "%s\n", jsonLine.c_str());
    std::fclose(f);
}

void captureViews(const Runtime& rt) {
    if (rt.captureDir.empty()) return;
    const char* names[2] = {"/left.png", "/right.png"};
    for (int eye = 0; eye < 2; ++eye) {
        const ViewImage& v = rt.lastViews[eye];
        if (v.rgba.empty()) continue;
        stbi_write_png((rt.captureDir + names[eye]).c_str(), v.width, v.height, 4, v.rgba.data(),
                       v.width * 4);
    }
}

const char* sessionStateName(XrSessionState state) {
    switch (state) {
        case XR_SESSION_STATE_IDLE:
            return "IDLE";
        case XR_SESSION_STATE_READY:
            return "READY";
        case XR_SESSION_STATE_SYNCHRONIZED:
            return "SYNCHRONIZED";
        case XR_SESSION_STATE_VISIBLE:
            return "VISIBLE";
        case XR_SESSION_STATE_FOCUSED:
            return "FOCUSED";
        case XR_SESSION_STATE_STOPPING:
            return "STOPPING";
        case XR_SESSION_STATE_LOSS_PENDING:
            return "LOSS_PENDING";
        case XR_SESSION_STATE_EXITING:
            return "EXITING";
        default:
            return "UNKNOWN";
    }
}

}  // namespace kizamu::xrsim
