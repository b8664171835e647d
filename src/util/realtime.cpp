// SPDX-License-Identifier: Apache-2.0
/// @file realtime.cpp
/// @brief setRealtimePriority, lockMemory and CpuDmaLatency over pthreads, mlockall and the
/// PM QoS device.
#include "util/realtime.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <utility>

#if defined(__linux__)
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace kizamu::util {

namespace {

bool fail(std::string* why, std::string reason) {
    if (why) *why = std::move(reason);
    return false;
}

}  // namespace

#if defined(__linux__)

bool setRealtimePriority(int priority, std::string* why) {
    const int lowest = sched_get_priority_min(SCHED_FIFO),
              highest = sched_get_priority_max(SCHED_FIFO);
    if (priority < lowest || priority > highest)
        return fail(why, "real-time priority " + std::to_string(priority) + " is outside " +
                             std::to_string(lowest) + ".." + std::to_string(highest));
    sched_param param{};
    param.sched_priority = priority;
    const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (error == 0) return true;
    if (error == EPERM)
        return fail(why, "no real-time priority: needs root or CAP_SYS_NICE / RLIMIT_RTPRIO");
    return fail(why, std::string("no real-time priority: ") + std::strerror(error));
}

bool lockMemory(std::string* why) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return true;
    const int error = errno;
    if (error == EPERM || error == ENOMEM)
        return fail(
            why, std::string("memory not locked (") + std::strerror(error) +
                     "): needs root or CAP_IPC_LOCK / an RLIMIT_MEMLOCK as large as the process");
    return fail(why, std::string("memory not locked: ") + std::strerror(error));
}

CpuDmaLatency::CpuDmaLatency() {
    const int fd = ::open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
    if (fd < 0) {
        const int error = errno;
        mReason = std::string("cannot open /dev/cpu_dma_latency: ") + std::strerror(error) +
                  (error == EACCES || error == EPERM ? " (needs root)" : "");
        return;
    }
    // The request is a 32-bit latency in microseconds; it holds while the file stays open.
    const int32_t latencyUs = 0;
    if (::write(fd, &latencyUs, sizeof latencyUs) != ssize_t(sizeof latencyUs)) {
        mReason = std::string("cannot write to /dev/cpu_dma_latency: ") + std::strerror(errno);
        ::close(fd);
        return;
    }
    mFd = fd;
}

CpuDmaLatency::~CpuDmaLatency() {
    if (mFd >= 0) ::close(mFd);
}

#else

bool setRealtimePriority(int, std::string* why) {
    return fail(why, "real-time priority is not supported on this platform");
}
bool lockMemory(std::string* why) {
    return fail(why, "locking memory is not supported on this platform");
}
CpuDmaLatency::CpuDmaLatency()
    : mReason("/dev/cpu_dma_latency is not available on this platform") {}
CpuDmaLatency::~CpuDmaLatency() = default;

#endif

CpuDmaLatency::CpuDmaLatency(CpuDmaLatency&& other) noexcept
    : mFd(std::exchange(other.mFd, -1)), mReason(std::move(other.mReason)) {
    other.mReason = "moved from";
}

CpuDmaLatency& CpuDmaLatency::operator=(CpuDmaLatency&& other) noexcept {
    if (this != &other) {
        CpuDmaLatency old(std::move(*this));  // releases ours on scope exit
        mFd = std::exchange(other.mFd, -1);
        mReason = std::move(other.mReason);
        other.mReason = "moved from";
    }
    return *this;
}

}  // namespace kizamu::util
