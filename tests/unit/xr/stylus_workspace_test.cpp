// SPDX-License-Identifier: Apache-2.0
#include "xr/stylus_workspace.h"

#include "util/file_error.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace kizamu::xr {
namespace {

namespace fs = std::filesystem;

Similarity registration() {
    Similarity s;
    s.rotation = glm::normalize(glm::angleAxis(0.4, glm::normalize(glm::dvec3(1.0, 2.0, -0.5))));
    s.scale = 1.3;
    s.translation = {0.05, -0.2, -0.3};
    return s;
}

TEST(StylusWorkspace, TheStylusFeelsTheClayWhereTheHeadsetShowsIt) {
    const Similarity deviceToSpace = registration();
    Similarity placement = defaultClayPlacement(glm::dvec3(0.1), 0.2);
    placement.scale = 1.7;  // the artist has scaled the clay up
    const haptics::WorkspaceMapping m = stylusMapping(deviceToSpace, placement);
    for (const glm::dvec3 device : {glm::dvec3(0.0), glm::dvec3(0.03, -0.02, 0.05), glm::dvec3(-0.06, 0.01, 0.0)}) {
        // The clay point the stylus touches, shown by the headset, is where the stylus tip is.
        const glm::dvec3 clay = m.toWorld(device);
        EXPECT_LT(glm::length(placement.apply(clay) - deviceToSpace.apply(device)), 1e-12);
        EXPECT_LT(glm::length(m.toDevice(clay) - device), 1e-12);
    }
}

TEST(StylusWorkspace, ARegistrationSurvivesTheFileAndABadFileIsAClearError) {
    const fs::path dir = fs::temp_directory_path() / ("kizamu_stylus_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const std::string path = (dir / "kizamu" / "stylus-registration.json").string();
    EXPECT_FALSE(loadStylusRegistration(path)) << "a missing file is no registration, not an error";
    StylusRegistration r;
    r.deviceToSpace = registration();
    r.rmsM = 0.0012;
    saveStylusRegistration(path, r, "Novint Falcon");
    const auto back = loadStylusRegistration(path);
    ASSERT_TRUE(back);
    EXPECT_NEAR(back->deviceToSpace.scale, r.deviceToSpace.scale, 1e-12);
    EXPECT_NEAR(back->rmsM, r.rmsM, 1e-15);
    const glm::dvec3 p(0.01, 0.02, 0.03);
    EXPECT_LT(glm::length(back->deviceToSpace.apply(p) - r.deviceToSpace.apply(p)), 1e-12);

    for (const char* bad : {"{", "{\"kizamu_stylus_registration\": 1, \"scale\": 1}", "[1, 2]",
                            "{\"kizamu_stylus_registration\": 1, \"scale\": 1, \"rotation\": [0,0,0,0], \"translation\": [0,0,0], \"rms_m\": 0}"}) {
        std::ofstream(path) << bad;
        try {
            loadStylusRegistration(path);
            ADD_FAILURE() << "accepted " << bad;
        } catch (const FileError& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        }
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace kizamu::xr
