// SPDX-License-Identifier: Apache-2.0
/// @file fuzz_kza.cpp
/// @brief libFuzzer harness for the .kza loader: any input is either a FileError or a snapshot
/// that answers queries; anything else (a crash, a sanitizer report, another exception) is a bug.
#include "adf/adf_file.h"
#include "adf/colour_layer.h"
#include "util/file_error.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    try {
        const kizamu::adf::AdfPtr adf =
            kizamu::adf::decodeAdf(std::string(reinterpret_cast<const char*>(data), size), "fuzz.kza");
        // A file that loads must be fully usable: walk every tile and query a few points.
        (void)adf->computeStats();
        const glm::vec3 lo = adf->originWorldF();
        const float size3 = float(adf->domain().sizeWorld);
        for (int i = 0; i <= 4; ++i) (void)adf->sample(lo + glm::vec3(float(i) * 0.25f * size3));
        kizamu::adf::AdfAccessor acc(*adf);
        for (int i = 0; i <= 4; ++i) (void)acc.sample(lo + glm::vec3(float(i) * 0.25f * size3, 0.5f * size3, 0.1f * size3));
        // Paint, if any: every painted point and blends between them, also past the domain.
        if (const auto& paint = adf->colours()) {
            (void)paint->pointCount();
            kizamu::adf::ColourAccessor colours(*paint);
            for (int i = -1; i <= 5; ++i) (void)colours.colourAt(lo + glm::vec3(float(i) * 0.23f * size3, 0.5f * size3, 0.37f * size3));
            for (std::size_t s = 0; s < paint->slotCount(); ++s) (void)paint->tileAt(paint->slotKeys()[s])->find(0);
        }
    } catch (const kizamu::FileError&) {
    }
    return 0;
}
