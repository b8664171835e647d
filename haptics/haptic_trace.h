// SPDX-License-Identifier: Apache-2.0
/// @file haptic_trace.h
/// @brief A record of every servo tick (device, proxy, force, contact), handed from the servo
/// thread to a writer through a wait-free ring, and the trace file it is written to
/// (docs/HAPTIC-TRACE.md): one JSON object per tick, so the physics can be checked from
/// outside the program.
///
/// The servo thread only push()es into a ring allocated before it starts (no allocation, no
/// lock, no I/O); a writer drains it, in lock step on the same thread between ticks, in real
/// time on its own thread every few milliseconds. A full ring drops the newest record and counts
/// it (the trace says how many it lost; the servo loop never waits for the disk).
#pragma once

#include "haptics/device.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace kizamu::haptics {

/// One servo tick, in the clay's world frame (SI units).
struct TraceRecord {
    int64_t timeNs = 0;         ///< the servo clock
    glm::dvec3 device{0.0};     ///< m, the device's end effector mapped into the world
    glm::dvec3 velocity{0.0};   ///< m/s, its velocity in the world
    glm::dvec3 proxy{0.0};      ///< m, the proxy (the tool the engine carves with)
    glm::dvec3 force{0.0};      ///< N, the force rendered (world axes)
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  ///< the tool's orientation in the world
    uint32_t buttons = 0;
    bool contact = false;
    bool clutched = false;      ///< the clutch held the tool still
};

/// Single producer (the servo thread), single consumer (the writer). Capacity fixed at
/// construction. push() and pop() are wait-free and allocate nothing.
class TraceRing {
public:
    /// @param capacity records, rounded up to a power of two (>= 2). Allocates. Cold path.
    explicit TraceRing(std::size_t capacity);
    /// Producer. False (and one more dropped()) when full.
    bool push(const TraceRecord& r) noexcept;
    /// Consumer. False when empty.
    bool pop(TraceRecord& r) noexcept;
    uint64_t dropped() const noexcept { return mDropped.load(std::memory_order_relaxed); }

private:
    std::unique_ptr<TraceRecord[]> mSlots;
    std::size_t mMask;
    alignas(64) std::atomic<uint64_t> mHead{0};  ///< next to write (producer)
    alignas(64) std::atomic<uint64_t> mTail{0};  ///< next to read (consumer)
    std::atomic<uint64_t> mDropped{0};
};

/// The trace file's first line: {"device", "max_force", "stiffness", "damping", "rate", ...}.
struct TraceHeader {
    std::string device;
    double maxForce = 0.0;   ///< N
    double stiffness = 0.0;  ///< N/m, the renderer's wall as the device feels it
    double damping = 0.0;    ///< N·s/m, the renderer's virtual damping as the device feels it
    double rate = 0.0;       ///< Hz
    double deviceDamping = 0.0;  ///< N·s/m, the device's physical damping
    double scale = 1.0;      ///< world m per device m
};

/// One line of JSON (no newline) for the header / a record; `t` is in seconds from `t0Ns`.
std::string formatTraceHeader(const TraceHeader& h);
std::string formatTraceRecord(const TraceRecord& r, int64_t t0Ns);

/// Writes the trace file. Cold-path class; drain() on the consumer side of one ring.
class TraceFile {
public:
    /// Creates `path` and writes the header. @throw kizamu::FileError when it cannot.
    TraceFile(const std::string& path, const TraceHeader& header);
    ~TraceFile();
    TraceFile(const TraceFile&) = delete;
    TraceFile& operator=(const TraceFile&) = delete;
    /// Writes every record in the ring; `t` counts from the first record ever written. Calls
    /// `each` (if set) with each record. Returns how many it wrote.
    /// @throw kizamu::FileError on a write error
    template <class Each>
    std::size_t drain(TraceRing& ring, Each&& each) {
        TraceRecord r;
        std::size_t n = 0;
        while (ring.pop(r)) {
            if (!mStarted) {
                mT0Ns = r.timeNs;
                mStarted = true;
            }
            writeLine(formatTraceRecord(r, mT0Ns));
            each(r);
            ++n;
        }
        return n;
    }
    std::size_t drain(TraceRing& ring) {
        return drain(ring, [](const TraceRecord&) {});
    }
    /// Flushes and closes. @throw kizamu::FileError on a write error
    void close();

private:
    void writeLine(const std::string& line);
    std::string mPath;
    std::FILE* mFile = nullptr;
    int64_t mT0Ns = 0;
    bool mStarted = false;
};

}  // namespace kizamu::haptics
