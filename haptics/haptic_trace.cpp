// SPDX-License-Identifier: Apache-2.0
/// @file haptic_trace.cpp
/// @brief TraceRing, the trace file's lines, TraceFile.
#include "haptics/haptic_trace.h"

#include "util/file_error.h"

#include <cerrno>
#include <cmath>
#include <cstring>

namespace kizamu::haptics {

TraceRing::TraceRing(std::size_t capacity) {
    std::size_t n = 2;
    while (n < capacity) n *= 2;
    mSlots = std::make_unique<TraceRecord[]>(n);
    mMask = n - 1;
}

bool TraceRing::push(const TraceRecord& r) noexcept {
    const uint64_t head = mHead.load(std::memory_order_relaxed);
    if (head - mTail.load(std::memory_order_acquire) > mMask) {
        mDropped.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    mSlots[head & mMask] = r;
    mHead.store(head + 1, std::memory_order_release);
    return true;
}

bool TraceRing::pop(TraceRecord& r) noexcept {
    const uint64_t tail = mTail.load(std::memory_order_relaxed);
    if (tail == mHead.load(std::memory_order_acquire)) return false;
    r = mSlots[tail & mMask];
    mTail.store(tail + 1, std::memory_order_release);
    return true;
}

namespace {

/// A finite number as JSON (%.9g: nm and µN resolution at the scales involved); a non-finite
/// one as null, which JSON readers take and no renderer output ever is.
void appendNumber(std::string& s, double v) {
    if (!std::isfinite(v)) {
        s += "null";
        return;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    s += buf;
}

void appendVector(std::string& s, const char* key, const glm::dvec3& v) {
    s += ", \"";
    s += key;
    s += "\": [";
    appendNumber(s, v.x);
    s += ", ";
    appendNumber(s, v.y);
    s += ", ";
    appendNumber(s, v.z);
    s += ']';
}

void appendField(std::string& s, const char* key, double v) {
    s += ", \"";
    s += key;
    s += "\": ";
    appendNumber(s, v);
}

std::string jsonString(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += c;
        }
    }
    return out + '"';
}

}  // namespace

std::string formatTraceHeader(const TraceHeader& h) {
    std::string s = "{\"device\": " + jsonString(h.device);
    appendField(s, "max_force", h.maxForce);
    appendField(s, "stiffness", h.stiffness);
    appendField(s, "damping", h.damping);
    appendField(s, "rate", h.rate);
    appendField(s, "device_damping", h.deviceDamping);
    appendField(s, "scale", h.scale);
    s += ", \"kizamu_haptic_trace\": 1}";
    return s;
}

std::string formatTraceRecord(const TraceRecord& r, int64_t t0Ns) {
    std::string s = "{\"t\": ";
    appendNumber(s, double(r.timeNs - t0Ns) * 1e-9);
    appendVector(s, "device", r.device);
    appendVector(s, "velocity", r.velocity);
    appendVector(s, "proxy", r.proxy);
    appendVector(s, "force", r.force);
    s += r.contact ? ", \"contact\": true" : ", \"contact\": false";
    s += ", \"buttons\": " + std::to_string(r.buttons);
    if (r.clutched) s += ", \"clutched\": true";
    s += '}';
    return s;
}

TraceFile::TraceFile(const std::string& path, const TraceHeader& header) : mPath(path) {
    mFile = std::fopen(path.c_str(), "wb");
    if (!mFile) throw FileError(path, std::string("cannot create: ") + std::strerror(errno));
    writeLine(formatTraceHeader(header));
}

TraceFile::~TraceFile() {
    if (mFile) std::fclose(mFile);
}

void TraceFile::writeLine(const std::string& line) {
    if (!mFile) throw FileError(mPath, "written after close");
    if (std::fwrite(line.data(), 1, line.size(), mFile) != line.size() || std::fputc('\n', mFile) == EOF)
        throw FileError(mPath, std::string("write failed: ") + std::strerror(errno));
}

void TraceFile::close() {
    if (!mFile) return;
    std::FILE* f = mFile;
    mFile = nullptr;
    if (std::fclose(f) != 0) throw FileError(mPath, std::string("write failed: ") + std::strerror(errno));
}

}  // namespace kizamu::haptics
