// SPDX-License-Identifier: Apache-2.0
/// @file hid_report_descriptor.cpp
/// @brief The HID report descriptor parser and the PID layout search (sources: the header).
#include "haptics/hid/hid_report_descriptor.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

namespace kizamu::haptics::hid {

namespace {

/// The largest report this parser accepts (bits): far above any device's (USB full speed
/// interrupt reports are at most 64 bytes), so a size that overflows is caught.
constexpr uint64_t kMaxReportBits = 4096ull * 8ull;
/// Usage ranges are expanded into lists; a range longer than this keeps its first entries
/// (the PID and joystick usages this module looks for sit in short ranges).
constexpr uint32_t kMaxRangeUsages = 4096;

struct GlobalState {
    uint16_t usagePage = 0;
    int64_t logicalMin = 0, logicalMax = 0;
    int64_t logicalMaxUnsigned = 0;  ///< the Logical Maximum's bytes read unsigned
    uint32_t reportSize = 0, reportCount = 0;
    uint8_t reportId = 0;
};

struct LocalState {
    std::vector<uint32_t> usages;
    bool haveMin = false;
    uint32_t usageMin = 0;
    void clear() {
        usages.clear();
        haveMin = false;
    }
};

[[noreturn]] void fail(const char* what, std::size_t at) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "HID report descriptor: %s at byte %zu", what, at);
    throw HidDescriptorError(buf);
}

uint32_t unsignedData(const uint8_t* d, int size) {
    uint32_t v = 0;
    for (int i = 0; i < size; ++i) v |= uint32_t(d[i]) << (8 * i);
    return v;
}

int64_t signedData(const uint8_t* d, int size) {
    const uint32_t v = unsignedData(d, size);
    switch (size) {
        case 1: return int8_t(v);
        case 2: return int16_t(v);
        case 4: return int32_t(v);
        default: return 0;
    }
}

/// A usage item's extended usage: 4-byte data carries its own page, shorter data takes the
/// page in effect when the item is read.
uint32_t toExtended(uint32_t data, int size, uint16_t usagePage) {
    return size == 4 ? data : extendedUsage(usagePage, uint16_t(data));
}

}  // namespace

uint32_t HidReportDescriptor::reportBytes(ReportType type, uint8_t reportId) const noexcept {
    uint64_t bits = 0;
    bool any = false;
    for (const HidField& f : fields) {
        if (f.type != type || f.reportId != reportId) continue;
        any = true;
        bits = std::max<uint64_t>(bits, uint64_t(f.bitOffset) + uint64_t(f.bitSize) * f.count);
    }
    if (!any) return 0;
    return uint32_t((bits + 7) / 8) + (usesReportIds ? 1u : 0u);
}

bool HidReportDescriptor::hasPidUsages() const noexcept {
    auto onPid = [](uint32_t u) { return (u >> 16) == page::kPid; };
    if (std::any_of(topLevelUsages.begin(), topLevelUsages.end(), onPid)) return true;
    for (const HidField& f : fields)
        if (std::any_of(f.usages.begin(), f.usages.end(), onPid) ||
            std::any_of(f.collections.begin(), f.collections.end(), onPid))
            return true;
    return false;
}

HidReportDescriptor parseReportDescriptor(std::span<const uint8_t> bytes) {
    HidReportDescriptor out;
    GlobalState global;
    std::vector<GlobalState> pushed;
    LocalState local;
    std::vector<uint32_t> collections;
    // Next free bit per (type, report ID).
    std::map<std::pair<int, uint8_t>, uint64_t> nextBit;

    std::size_t i = 0;
    while (i < bytes.size()) {
        const std::size_t at = i;
        const uint8_t prefix = bytes[i++];
        if (prefix == 0xFE) {  // long item: size, tag, data; none is defined, so skip it
            if (i + 2 > bytes.size()) fail("truncated long item", at);
            const std::size_t size = bytes[i];
            i += 2 + size;
            if (i > bytes.size()) fail("truncated long item", at);
            continue;
        }
        const int size = (prefix & 0x3) == 3 ? 4 : (prefix & 0x3);
        const int type = (prefix >> 2) & 0x3;
        const int tag = prefix >> 4;
        if (i + std::size_t(size) > bytes.size()) fail("truncated item", at);
        const uint8_t* data = bytes.data() + i;
        i += std::size_t(size);
        const uint32_t u = unsignedData(data, size);

        if (type == 0) {  // main
            switch (tag) {
                case 0x8:    // Input
                case 0x9:    // Output
                case 0xB: {  // Feature
                    HidField f;
                    f.type = tag == 0x8 ? ReportType::Input : tag == 0x9 ? ReportType::Output : ReportType::Feature;
                    f.reportId = global.reportId;
                    f.bitSize = global.reportSize;
                    f.count = global.reportCount;
                    f.logicalMin = global.logicalMin;
                    f.logicalMax = global.logicalMax;
                    // A maximum below the minimum is an unsigned value written in the shortest
                    // form (0x26 0xFF 0xFF for 65535 with minimum 0): read it unsigned.
                    if (f.logicalMax < f.logicalMin) f.logicalMax = global.logicalMaxUnsigned;
                    f.isConstant = (u & 0x1) != 0;
                    f.isVariable = (u & 0x2) != 0;
                    f.collections = collections;
                    if (f.bitSize == 0 && f.count > 0) fail("main item with Report Size 0", at);
                    uint64_t& bit = nextBit[{int(f.type), f.reportId}];
                    f.bitOffset = uint32_t(bit);
                    bit += uint64_t(f.bitSize) * f.count;
                    if (bit > kMaxReportBits) fail("report longer than 4096 bytes", at);
                    if (f.isVariable) {
                        if (!local.usages.empty()) {
                            f.usages.reserve(f.count);
                            for (uint32_t k = 0; k < f.count; ++k)
                                f.usages.push_back(local.usages[std::min<std::size_t>(k, local.usages.size() - 1)]);
                        }
                    } else {
                        f.usages = local.usages;
                    }
                    out.fields.push_back(std::move(f));
                    break;
                }
                case 0xA: {  // Collection
                    const uint32_t usage = local.usages.empty() ? 0 : local.usages.front();
                    if (collections.empty()) out.topLevelUsages.push_back(usage);
                    collections.push_back(usage);
                    break;
                }
                case 0xC:  // End Collection
                    if (collections.empty()) fail("End Collection without Collection", at);
                    collections.pop_back();
                    break;
                default:
                    break;
            }
            local.clear();
        } else if (type == 1) {  // global
            switch (tag) {
                case 0x0: global.usagePage = uint16_t(u); break;
                case 0x1: global.logicalMin = signedData(data, size); break;
                case 0x2:
                    global.logicalMax = signedData(data, size);
                    global.logicalMaxUnsigned = int64_t(u);
                    break;
                case 0x7: global.reportSize = u; break;
                case 0x8:
                    if (u == 0 || u > 0xFF) fail("Report ID outside 1..255", at);
                    global.reportId = uint8_t(u);
                    out.usesReportIds = true;
                    break;
                case 0x9: global.reportCount = u; break;
                case 0xA: pushed.push_back(global); break;
                case 0xB:
                    if (pushed.empty()) fail("Pop without Push", at);
                    global = pushed.back();
                    pushed.pop_back();
                    break;
                default: break;  // physical range, units, exponent: not needed here
            }
        } else if (type == 2) {  // local
            switch (tag) {
                case 0x0: local.usages.push_back(toExtended(u, size, global.usagePage)); break;
                case 0x1:
                    local.usageMin = toExtended(u, size, global.usagePage);
                    local.haveMin = true;
                    break;
                case 0x2: {
                    if (!local.haveMin) fail("Usage Maximum without Usage Minimum", at);
                    const uint32_t usageMax = toExtended(u, size, global.usagePage);
                    for (uint32_t v = local.usageMin, n = 0; v <= usageMax && n < kMaxRangeUsages; ++v, ++n) {
                        local.usages.push_back(v);
                        if (v == 0xFFFFFFFFu) break;
                    }
                    local.haveMin = false;
                    break;
                }
                default: break;  // designators, strings, delimiters
            }
        } else {
            fail("reserved item type", at);
        }
    }
    if (!collections.empty()) fail("Collection without End Collection", bytes.size());
    return out;
}

// ---- findPidLayout ----

namespace {

FieldLocation locationOf(const HidField& f, uint32_t index) {
    FieldLocation loc;
    loc.bitOffset = f.bitOffset + index * f.bitSize;
    loc.bitSize = f.bitSize;
    loc.logicalMin = f.logicalMin;
    loc.logicalMax = f.logicalMax;
    return loc;
}

bool inCollection(const HidField& f, uint32_t usage) {
    return std::find(f.collections.begin(), f.collections.end(), usage) != f.collections.end();
}

/// The report ID of the first field of `type` inside a collection with `collectionUsage`; -1: none.
int reportOfCollection(const HidReportDescriptor& d, ReportType type, uint32_t collectionUsage) {
    for (const HidField& f : d.fields)
        if (f.type == type && inCollection(f, collectionUsage)) return f.reportId;
    return -1;
}

/// The value with `usage` in report (type, id): a variable field's value.
FieldLocation findValue(const HidReportDescriptor& d, ReportType type, uint8_t id, uint32_t usage,
                        uint32_t withinCollection = 0) {
    for (const HidField& f : d.fields) {
        if (f.type != type || f.reportId != id || f.isConstant || !f.isVariable) continue;
        if (withinCollection != 0 && !inCollection(f, withinCollection)) continue;
        for (uint32_t k = 0; k < f.usages.size(); ++k)
            if (f.usages[k] == usage) return locationOf(f, k);
    }
    return {};
}

/// How to select `usage` in report (type, id): an array field listing it, or a one-bit
/// variable field carrying it.
FieldChoice findChoice(const HidReportDescriptor& d, ReportType type, uint8_t id, uint32_t usage) {
    for (const HidField& f : d.fields) {
        if (f.type != type || f.reportId != id || f.isConstant) continue;
        for (uint32_t k = 0; k < f.usages.size(); ++k) {
            if (f.usages[k] != usage) continue;
            FieldChoice c;
            if (f.isVariable) {
                c.field = locationOf(f, k);
                c.value = 1;
            } else {
                c.field = locationOf(f, 0);
                c.value = f.logicalMin + int64_t(k);
            }
            return c;
        }
    }
    return {};
}

ReportLocation reportLocation(const HidReportDescriptor& d, ReportType type, int id) {
    if (id < 0) return {};
    return {uint8_t(id), d.reportBytes(type, uint8_t(id))};
}

[[noreturn]] void missing(const char* what) {
    throw HidDescriptorError(std::string("HID PID descriptor: no ") + what);
}

void checkSize(const ReportLocation& r, std::size_t maxBytes, const char* name) {
    if (r.present() && r.bytes > maxBytes) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "HID PID descriptor: the %s report has %u bytes, more than %zu", name,
                      r.bytes, maxBytes);
        throw HidDescriptorError(buf);
    }
}

constexpr uint32_t pidUsage(uint16_t id) { return extendedUsage(page::kPid, id); }
constexpr uint32_t desktopUsage(uint16_t id) { return extendedUsage(page::kGenericDesktop, id); }

}  // namespace

PidLayout findPidLayout(const HidReportDescriptor& d, std::size_t maxReportBytes) {
    if (!d.hasPidUsages())
        throw HidDescriptorError(
            "HID report descriptor has no Physical Interface Device (usage page 0x0F) usages: not a "
            "force-feedback device");
    PidLayout L;

    // Input: the first input report with a Generic Desktop axis; its axes and buttons.
    int inputId = -1;
    for (const HidField& f : d.fields) {
        if (f.type != ReportType::Input || f.isConstant || !f.isVariable) continue;
        for (uint32_t u : f.usages)
            if (u >= desktopUsage(desktop::kX) && u <= desktopUsage(desktop::kWheel)) inputId = f.reportId;
        if (inputId >= 0) break;
    }
    if (inputId < 0) missing("input report with a Generic Desktop axis (X, Y, ...)");
    L.input = reportLocation(d, ReportType::Input, inputId);
    bool buttonsFound = false;
    for (const HidField& f : d.fields) {
        if (f.type != ReportType::Input || f.reportId != inputId || f.isConstant || !f.isVariable) continue;
        for (uint32_t k = 0; k < f.usages.size(); ++k) {
            const uint32_t u = f.usages[k];
            if (u >= desktopUsage(desktop::kX) && u <= desktopUsage(desktop::kWheel) &&
                L.axisCount < PidLayout::kMaxAxes)
                L.axes[L.axisCount++] = {uint16_t(u & 0xFFFF), locationOf(f, k)};
        }
        if (!buttonsFound && f.bitSize == 1 && !f.usages.empty() && (f.usages.front() >> 16) == page::kButton) {
            buttonsFound = true;
            L.buttonsBitOffset = f.bitOffset;
            L.buttonCount = std::min<uint32_t>(f.count, PidLayout::kMaxButtons);
        }
    }

    // Set Effect.
    {
        const int id = reportOfCollection(d, ReportType::Output, pidUsage(pid::kSetEffectReport));
        if (id < 0) missing("Set Effect output report (0x21)");
        auto& s = L.setEffect;
        s.report = reportLocation(d, ReportType::Output, id);
        s.blockIndex = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kEffectBlockIndex));
        s.typeConstant = findChoice(d, ReportType::Output, uint8_t(id), pidUsage(pid::kEtConstantForce));
        if (!s.blockIndex.present()) missing("Effect Block Index in the Set Effect report");
        if (!s.typeConstant.present()) missing("ET Constant Force in the Set Effect report's Effect Type");
        s.duration = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kDuration));
        s.triggerRepeatInterval = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kTriggerRepeatInterval));
        s.samplePeriod = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kSamplePeriod));
        s.startDelay = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kStartDelay));
        s.gain = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kGain));
        s.triggerButton = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kTriggerButton));
        s.directionEnable = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kDirectionEnable));
        for (int a = 0; a < 2; ++a)
            s.axisEnable[a] = findValue(d, ReportType::Output, uint8_t(id), desktopUsage(uint16_t(desktop::kX + a)),
                                        pidUsage(pid::kAxesEnable));
        // Direction instances are Ordinal usages (page 0x0A, ID = instance) in the Direction
        // collection.
        for (int a = 0; a < 2; ++a)
            s.direction[a] = findValue(d, ReportType::Output, uint8_t(id), extendedUsage(0x0A, uint16_t(a + 1)),
                                       pidUsage(pid::kDirection));
    }

    // Set Constant Force.
    {
        const int id = reportOfCollection(d, ReportType::Output, pidUsage(pid::kSetConstantForceReport));
        if (id < 0) missing("Set Constant Force output report (0x73)");
        auto& c = L.constantForce;
        c.report = reportLocation(d, ReportType::Output, id);
        c.blockIndex = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kEffectBlockIndex));
        c.magnitude = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kMagnitude),
                                pidUsage(pid::kSetConstantForceReport));
        if (!c.blockIndex.present() || !c.magnitude.present())
            missing("Effect Block Index or Magnitude in the Set Constant Force report");
    }

    // Effect Operation.
    {
        const int id = reportOfCollection(d, ReportType::Output, pidUsage(pid::kEffectOperationReport));
        if (id < 0) missing("Effect Operation output report (0x77)");
        auto& e = L.effectOperation;
        e.report = reportLocation(d, ReportType::Output, id);
        e.blockIndex = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kEffectBlockIndex));
        e.start = findChoice(d, ReportType::Output, uint8_t(id), pidUsage(pid::kOpEffectStart));
        e.stop = findChoice(d, ReportType::Output, uint8_t(id), pidUsage(pid::kOpEffectStop));
        e.loopCount = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kLoopCount));
        if (!e.blockIndex.present() || !e.start.present() || !e.stop.present())
            missing("Effect Block Index, Op Effect Start or Op Effect Stop in the Effect Operation report");
    }

    // Device Control: whichever output report carries DC Enable Actuators.
    {
        int id = -1;
        for (const HidField& f : d.fields)
            if (f.type == ReportType::Output &&
                std::find(f.usages.begin(), f.usages.end(), pidUsage(pid::kDcEnableActuators)) != f.usages.end()) {
                id = f.reportId;
                break;
            }
        if (id < 0) missing("PID Device Control output report with DC Enable Actuators (0x97)");
        auto& c = L.deviceControl;
        c.report = reportLocation(d, ReportType::Output, id);
        c.enableActuators = findChoice(d, ReportType::Output, uint8_t(id), pidUsage(pid::kDcEnableActuators));
        c.disableActuators = findChoice(d, ReportType::Output, uint8_t(id), pidUsage(pid::kDcDisableActuators));
        c.stopAllEffects = findChoice(d, ReportType::Output, uint8_t(id), pidUsage(pid::kDcStopAllEffects));
        c.reset = findChoice(d, ReportType::Output, uint8_t(id), pidUsage(pid::kDcDeviceReset));
    }

    // Create New Effect and Block Load (features, together or not at all).
    {
        const int id = reportOfCollection(d, ReportType::Feature, pidUsage(pid::kCreateNewEffectReport));
        if (id >= 0) {
            auto& n = L.createNewEffect;
            n.report = reportLocation(d, ReportType::Feature, id);
            n.typeConstant = findChoice(d, ReportType::Feature, uint8_t(id), pidUsage(pid::kEtConstantForce));
            if (!n.typeConstant.present()) missing("ET Constant Force in the Create New Effect report");
            const int bl = reportOfCollection(d, ReportType::Feature, pidUsage(pid::kBlockLoadReport));
            if (bl < 0) missing("PID Block Load feature report (0x89), which Create New Effect needs");
            auto& b = L.blockLoad;
            b.report = reportLocation(d, ReportType::Feature, bl);
            b.blockIndex = findValue(d, ReportType::Feature, uint8_t(bl), pidUsage(pid::kEffectBlockIndex));
            b.success = findChoice(d, ReportType::Feature, uint8_t(bl), pidUsage(pid::kBlockLoadSuccess));
            if (!b.blockIndex.present() || !b.success.present())
                missing("Effect Block Index or Block Load Success in the Block Load report");
        }
    }

    // Device Gain (optional).
    {
        const int id = reportOfCollection(d, ReportType::Output, pidUsage(pid::kDeviceGainReport));
        if (id >= 0) {
            L.deviceGain.report = reportLocation(d, ReportType::Output, id);
            L.deviceGain.gain = findValue(d, ReportType::Output, uint8_t(id), pidUsage(pid::kDeviceGain));
            if (!L.deviceGain.gain.present()) L.deviceGain = {};
        }
    }

    checkSize(L.input, maxReportBytes, "input");
    checkSize(L.setEffect.report, maxReportBytes, "Set Effect");
    checkSize(L.constantForce.report, maxReportBytes, "Set Constant Force");
    checkSize(L.effectOperation.report, maxReportBytes, "Effect Operation");
    checkSize(L.deviceControl.report, maxReportBytes, "Device Control");
    checkSize(L.createNewEffect.report, maxReportBytes, "Create New Effect");
    checkSize(L.blockLoad.report, maxReportBytes, "Block Load");
    checkSize(L.deviceGain.report, maxReportBytes, "Device Gain");
    return L;
}

}  // namespace kizamu::haptics::hid
