// SPDX-License-Identifier: Apache-2.0
/// @file engine.cpp
/// @brief Engine's public face: construction and shutdown, the command queue, the mesh
/// mailbox, notices and counters. The edit thread's passes are in edit_pass.cpp.
#include "engine/engine.h"

#include "engine/edit_pass.h"
#include "util/file_error.h"

#include <stdexcept>
#include <utility>

namespace kizamu::engine {

Engine::Engine(EngineSettings settings)
    : mSettings(std::move(settings)), mCommands(std::make_unique<detail::CommandQueue>()), mMailbox(std::make_unique<detail::Mailbox>()),
      mCounters(std::make_unique<detail::Counters>()) {
    if (mSettings.producers == 0) throw std::invalid_argument("engine: at least one sample producer");
    for (std::size_t i = 0; i < mSettings.producers; ++i) mQueues.push_back(std::make_unique<SampleQueue>(mSettings.queue));
    mEdit = std::make_unique<detail::EditPass>(mSettings, mQueues, *mMailbox, *mCounters, mStroking, mFullMeshWanted);
    mStore = std::make_unique<adf::SnapshotStore>(mEdit->current());
    mEdit->start(*mStore);
    mThread = std::thread([this] { mEdit->run(*mCommands); });
}

Engine::~Engine() {
    {
        std::lock_guard lock(mCommands->mutex);
        mCommands->stop = true;
    }
    mCommands->wake.notify_all();
    if (mThread.joinable()) mThread.join();
}

std::future<CommandResult> Engine::enqueue(detail::Command command) {
    std::future<CommandResult> result = command.result.get_future();
    {
        std::lock_guard lock(mCommands->mutex);
        if (!mCommands->stop) {
            mCommands->pending.push_back(std::move(command));
            mCommands->wake.notify_one();
            return result;
        }
    }
    command.result.set_value({false, "the engine stopped"});
    return result;
}

std::future<CommandResult> Engine::setTool(ToolSettings tool) {
    detail::Command c{detail::Command::Kind::SetTool};
    c.tool = std::move(tool);
    return enqueue(std::move(c));
}

std::future<CommandResult> Engine::undo() { return enqueue(detail::Command{detail::Command::Kind::Undo}); }
std::future<CommandResult> Engine::redo() { return enqueue(detail::Command{detail::Command::Kind::Redo}); }
std::future<CommandResult> Engine::cancelStroke() { return enqueue(detail::Command{detail::Command::Kind::Cancel}); }
std::future<CommandResult> Engine::sync() { return enqueue(detail::Command{detail::Command::Kind::Sync}); }

std::future<CommandResult> Engine::save(std::string path) {
    detail::Command c{detail::Command::Kind::Save};
    c.path = std::move(path);
    return enqueue(std::move(c));
}

std::future<CommandResult> Engine::exportMesh(std::string path, std::string unit, double decimate) {
    detail::Command c{detail::Command::Kind::Export};
    c.path = std::move(path);
    c.unit = std::move(unit);
    c.decimate = decimate;
    return enqueue(std::move(c));
}

std::future<CommandResult> Engine::newSession(std::string dir, sculpt::Script start, int level) {
    detail::Command c{detail::Command::Kind::New};
    c.path = std::move(dir);
    c.script = std::move(start);
    c.level = level;
    return enqueue(std::move(c));
}

std::future<CommandResult> Engine::openSession(std::string dir) {
    detail::Command c{detail::Command::Kind::Open};
    c.path = std::move(dir);
    return enqueue(std::move(c));
}

std::future<CommandResult> Engine::saveSessionAs(std::string dir) {
    detail::Command c{detail::Command::Kind::SaveAs};
    c.path = std::move(dir);
    return enqueue(std::move(c));
}

std::future<CommandResult> Engine::importMesh(std::string meshPath, std::string dir, int level, std::string unit) {
    detail::Command c{detail::Command::Kind::Import};
    c.path = std::move(meshPath);
    c.dir = std::move(dir);
    c.level = level;
    c.unit = std::move(unit);
    return enqueue(std::move(c));
}

std::optional<mesh::MeshDelta> Engine::takeMeshDelta() {
    std::unique_lock lock(mMailbox->mutex, std::try_to_lock);
    if (!lock.owns_lock() || !mMailbox->delta) return std::nullopt;
    std::optional<mesh::MeshDelta> d = std::move(mMailbox->delta);
    mMailbox->delta.reset();
    return d;
}

std::vector<std::string> Engine::takeNotices() {
    std::lock_guard lock(mMailbox->noticeMutex);
    return std::exchange(mMailbox->notices, {});
}

EngineStats Engine::stats() const {
    const detail::Counters& c = *mCounters;
    auto get = [](const std::atomic<uint64_t>& a) { return a.load(std::memory_order_relaxed); };
    return {get(c.segments), get(c.strokes), get(c.cancelled), get(c.meshUpdates), get(c.superseded), get(c.checkpoints), get(c.corrections), get(c.retired)};
}

}  // namespace kizamu::engine
