// SPDX-License-Identifier: Apache-2.0
#include "app/headset_mode.h"

#include "xr/controller_automation.h"
#include "xr/controllers.h"
#include "xr/headset_session.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <vector>

namespace kizamu::app {

namespace {
using Clock = std::chrono::steady_clock;
}

struct HeadsetMode::Impl {
    xr::HeadsetSession session;
    xr::Controllers controllers;
    std::unique_ptr<xr::ControllerAutomation> automation;
    xr::SculptControls controls;
    xr::ControllerFrame hands;
    xr::FrameTiming timing;
    XrTime lastTime = 0;
    Clock::time_point frameStart{};
    std::deque<double> frameMs;
    bool vibrating = false;
    std::deque<interact::ControllerInput> scripted;  ///< waiting for the runtime's profile

    /// Plays the scripted events whose hand has a profile, in order (a later event of a hand
    /// never overtakes an earlier one).
    void playScripted() {
        while (!scripted.empty()) {
            const interact::ControllerInput& c = scripted.front();
            const std::string profile = controllers.currentProfile(c.hand == 0 ? xr::Hand::Left : xr::Hand::Right);
            if (profile.empty()) return;
            automation->apply(c, profile);
            scripted.pop_front();
        }
    }

    Impl(const HeadsetModeOptions& o)
        : session([&] {
              xr::HeadsetOptions h;
              h.validation = o.validation;
              return h;
          }()),
          controllers(session.instance(), session.session()), controls(xr::ControlsSettings{o.dominant}) {
        if (session.hasAutomation())
            automation = std::make_unique<xr::ControllerAutomation>(session.instance(), session.session(), session.space());
    }

    xr::PanelQuad panel() const {
        xr::PanelQuad q;
        q.pose = session.panelPose;
        q.sizeM = session.panelSizeM();
        q.pixels = session.panelPixels();
        return q;
    }
};

HeadsetMode::HeadsetMode(const HeadsetModeOptions& options)
    : mImpl(std::make_unique<Impl>(options)), mPlacement(xr::defaultClayPlacement(options.clayCentre, options.domainSize)) {}

HeadsetMode::~HeadsetMode() = default;

bool HeadsetMode::alive() { return mImpl->session.pollEvents(); }
bool HeadsetMode::running() const { return mImpl->session.running(); }
bool HeadsetMode::focused() const { return mImpl->session.focused(); }
bool HeadsetMode::lost() const { return mImpl->session.state() == XR_SESSION_STATE_LOSS_PENDING; }
void HeadsetMode::requestExit() { mImpl->session.requestExit(); }

bool HeadsetMode::play(const interact::ControllerInput& input) {
    if (!mImpl->automation) return false;
    mImpl->scripted.push_back(input);
    return true;
}

const xr::SculptIntent& HeadsetMode::beginFrame() {
    Impl& m = *mImpl;
    m.timing = m.session.beginFrame();
    m.frameStart = Clock::now();
    if (m.automation) m.playScripted();
    m.hands = m.controllers.read(m.session.space(), m.timing.displayTime);
    const double dtS = m.lastTime > 0 ? double(m.timing.displayTime - m.lastTime) * 1e-9 : double(m.timing.displayPeriod) * 1e-9;
    m.lastTime = m.timing.displayTime;
    mIntent = m.controls.update(m.hands, std::clamp(dtS, 0.0, 0.1), m.panel(), mPlacement);
    return mIntent;
}

ui::PanelPointer HeadsetMode::panelPointer() const {
    ui::PanelPointer p;
    p.displaySize = glm::vec2(mImpl->session.panelPixels());
    if (mIntent.pointer) p.position = glm::vec2(*mIntent.pointer);
    p.down = mIntent.pointerDown;
    return p;
}

void HeadsetMode::drawEyes(const render::ClayRenderer& renderer, const render::RenderSettings& settings,
                           const render::ToolMark* tool) {
    Impl& m = *mImpl;
    if (!m.timing.shouldRender) return;
    const glm::mat4 clayToSpace(mPlacement.matrix());
    const xr::Similarity spaceToClay = mPlacement.inverse();
    render::RenderSettings look = settings;
    look.ground = false;  // the headset has its own floor: the room
    look.samples = 1;
    for (int i = 0; i < 2; ++i) {
        const xr::EyeView& eye = m.session.eyes()[std::size_t(i)];
        render::ViewSetup v;
        v.view = eye.view * clayToSpace;
        v.projection = eye.projection;
        v.viewportHeight = eye.size.y;
        v.eye = glm::vec3(spaceToClay.apply(eye.pose.position));
        m.session.acquireEye(i);
        renderer.draw(v, look, tool);
        m.session.releaseEye(i);
    }
}

void HeadsetMode::beginPanel() {
    mImpl->session.acquirePanel();
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void HeadsetMode::endPanel() { mImpl->session.releasePanel(); }

void HeadsetMode::endFrame() {
    Impl& m = *mImpl;
    m.session.endFrame(true);
    ++mFrames;
    m.frameMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - m.frameStart).count());
    if (m.frameMs.size() > 240) m.frameMs.pop_front();
}

double HeadsetMode::medianFrameMs() const {
    std::vector<double> ms(mImpl->frameMs.begin(), mImpl->frameMs.end());
    if (ms.empty()) return 0.0;
    std::nth_element(ms.begin(), ms.begin() + std::ptrdiff_t(ms.size() / 2), ms.end());
    return ms[ms.size() / 2];
}

void HeadsetMode::mirror(int width, int height) const {
    const glm::ivec2 eye = mImpl->session.eyes()[0].size;
    if (eye.x <= 0 || eye.y <= 0) return;
    const double scale = std::min(double(width) / eye.x, double(height) / eye.y);
    const int w = int(eye.x * scale), h = int(eye.y * scale), x = (width - w) / 2, y = (height - h) / 2;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, mImpl->session.eyeFramebuffer(0));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glBlitFramebuffer(0, 0, eye.x, eye.y, x, y, x + w, y + h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void HeadsetMode::contact(double depth, double radius) {
    Impl& m = *mImpl;
    const xr::Hand hand = m.controls.settings().dominant;
    if (depth <= 0.0 || radius <= 0.0) {
        if (m.vibrating) m.controllers.stopVibration(hand);
        m.vibrating = false;
        return;
    }
    // Felt from the first touch, stronger the deeper: a pulse lasting two frames, renewed each
    // frame while in contact, so it stops by itself if the loop stalls.
    const float amplitude = float(std::clamp(0.2 + 0.8 * depth / radius, 0.2, 1.0));
    m.controllers.vibrate(hand, amplitude, 2 * std::max<XrDuration>(m.timing.displayPeriod, 1'000'000));
    m.vibrating = true;
}

std::string HeadsetMode::describe() const {
    const std::string profile = mImpl->controllers.currentProfile(mImpl->controls.settings().dominant);
    return "OpenXR: " + mImpl->session.runtimeName() + (profile.empty() ? "" : ", " + profile.substr(profile.rfind('/') + 1));
}

}  // namespace kizamu::app
