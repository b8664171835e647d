// SPDX-License-Identifier: Apache-2.0
/// @file hid_report_descriptor.h
/// @brief A HID report descriptor parser, and the layout of the reports a force-feedback
/// (HID PID, usage page 0x0F) device needs to stream a constant force and report its axes.
///
/// Where it sits: pure code under haptics/hid/. parseReportDescriptor() turns descriptor bytes
/// into a flat list of fields (one per Input, Output or Feature main item), with each field's
/// report, bit offset, size, count, logical range, usages and the collections around it;
/// findPidLayout() picks from them the fields hid_pid_codec.h encodes and decodes. No I/O, no
/// threads: the bytes come from the caller (on Linux, sysfs
/// /sys/class/hidraw/hidrawN/device/report_descriptor; hid_pid_device.h reads it).
/// Threading: free functions on caller-owned data, any thread. Cold path (it allocates).
///
/// Sources of the facts used (no code taken from them):
///  - Device Class Definition for HID 1.11 (usb.org), §6.2.2: the item format (short items:
///    prefix bits 0-1 size 0/1/2/4 bytes, bits 2-3 type main/global/local, bits 4-7 tag; long
///    items 0xFE), the main tags (Input 8, Output 9, Feature 0xB, Collection 0xA, End Collection
///    0xC), global tags (Usage Page 0, Logical Min 1, Logical Max 2, Report Size 7, Report ID 8,
///    Report Count 9, Push 0xA, Pop 0xB, ...), local tags (Usage 0, Usage Min 1, Usage Max 2),
///    4-byte usages as extended usages (page in the high 16 bits), a Variable item's last usage
///    repeating for the remaining values, and an Array item's value selecting usage
///    usageMin + (value - logicalMin).
///  - HID Usage Tables (usb.org): Generic Desktop page 0x01 (Joystick 0x04, X 0x30 .. Wheel 0x38),
///    Button page 0x09.
///  - Device Class Definition for Physical Interface Devices (PID) 1.0 (usb.org, pid1_01.pdf),
///    usage page 0x0F: the usage IDs listed in namespace pid below. The same IDs label the PID
///    reports in OpenFFBoard's published descriptor (github.com/Ultrawipf/OpenFFBoard,
///    Firmware/FFBoard/UserExtensions/Src/usb_hid_1ffb_desc.c), which shows both encodings of
///    the Device Control choice this parser accepts: a one-byte array (the spec's example) and
///    one bit per command (OpenFFBoard).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace kizamu::haptics::hid {

/// A descriptor this module cannot use: malformed bytes, or no PID reports (the message says
/// which report or field is missing).
class HidDescriptorError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// An extended usage: page in the high 16 bits, usage ID in the low 16.
constexpr uint32_t extendedUsage(uint16_t page, uint16_t id) noexcept {
    return (uint32_t(page) << 16) | id;
}

namespace page {
constexpr uint16_t kGenericDesktop = 0x01;
constexpr uint16_t kButton = 0x09;
constexpr uint16_t kPid = 0x0F;  ///< Physical Interface Device (force feedback)
}  // namespace page

/// Generic Desktop usages (HID Usage Tables).
namespace desktop {
constexpr uint16_t kJoystick = 0x04, kGamepad = 0x05, kMultiAxis = 0x08;
constexpr uint16_t kX = 0x30, kY = 0x31, kZ = 0x32, kRx = 0x33, kRy = 0x34, kRz = 0x35;
constexpr uint16_t kSlider = 0x36, kDial = 0x37, kWheel = 0x38;
}  // namespace desktop

/// PID 1.0 usages (usage page 0x0F) this module looks for.
namespace pid {
constexpr uint16_t kSetEffectReport = 0x21, kEffectBlockIndex = 0x22, kEffectType = 0x25;
constexpr uint16_t kEtConstantForce = 0x26;
constexpr uint16_t kDuration = 0x50, kSamplePeriod = 0x51, kGain = 0x52, kTriggerButton = 0x53;
constexpr uint16_t kTriggerRepeatInterval = 0x54, kAxesEnable = 0x55, kDirectionEnable = 0x56;
constexpr uint16_t kDirection = 0x57, kStartDelay = 0xA7;
constexpr uint16_t kMagnitude = 0x70, kSetConstantForceReport = 0x73;
constexpr uint16_t kEffectOperationReport = 0x77, kEffectOperation = 0x78;
constexpr uint16_t kOpEffectStart = 0x79, kOpEffectStartSolo = 0x7A, kOpEffectStop = 0x7B;
constexpr uint16_t kLoopCount = 0x7C, kDeviceGainReport = 0x7D, kDeviceGain = 0x7E;
constexpr uint16_t kBlockLoadReport = 0x89, kBlockLoadStatus = 0x8B;
constexpr uint16_t kBlockLoadSuccess = 0x8C, kBlockLoadFull = 0x8D, kBlockLoadError = 0x8E;
constexpr uint16_t kStateReport = 0x92;
constexpr uint16_t kDeviceControlReport = 0x95, kDeviceControl = 0x96;
constexpr uint16_t kDcEnableActuators = 0x97, kDcDisableActuators = 0x98;
constexpr uint16_t kDcStopAllEffects = 0x99, kDcDeviceReset = 0x9A;
constexpr uint16_t kCreateNewEffectReport = 0xAB;
}  // namespace pid

enum class ReportType : uint8_t { Input, Output, Feature };

/// One Input, Output or Feature main item: `count` values of `bitSize` bits each, starting at
/// `bitOffset` bits after the report ID byte (after nothing when the descriptor has no report
/// IDs). Plain data.
struct HidField {
    ReportType type = ReportType::Input;
    uint8_t reportId = 0;       ///< 0: the descriptor declares no report IDs
    uint32_t bitOffset = 0;
    uint32_t bitSize = 0;       ///< bits per value
    uint32_t count = 0;         ///< values
    int64_t logicalMin = 0, logicalMax = 0;
    bool isConstant = false;    ///< padding or a constant (no usage to it)
    bool isVariable = false;    ///< one value per usage; false: an array of usage selectors
    /// Extended usages. Variable: one per value (`count` entries; the last declared usage
    /// repeats). Array: the usages the values select among, in order (value logicalMin selects
    /// usages[0]).
    std::vector<uint32_t> usages;
    /// Extended usages of the enclosing collections, outermost first.
    std::vector<uint32_t> collections;
};

/// A parsed descriptor. Plain data; produced by parseReportDescriptor().
struct HidReportDescriptor {
    std::vector<HidField> fields;              ///< in descriptor order
    std::vector<uint32_t> topLevelUsages;      ///< extended usages of the top-level collections
    bool usesReportIds = false;

    /// Bytes of report (type, id) as sent or received, the report ID byte included when the
    /// descriptor uses report IDs; 0 when no field belongs to it. Complexity: O(fields).
    uint32_t reportBytes(ReportType type, uint8_t reportId) const noexcept;
    /// Whether any usage or collection is on the PID page (0x0F). Complexity: O(fields).
    bool hasPidUsages() const noexcept;
};

/// Parses report descriptor bytes (HID 1.11 §6.2.2).
/// @throw HidDescriptorError on truncated items, unbalanced collections, Pop without Push,
///        a report over 4096 bytes or a field without a size.
/// Complexity: O(bytes + fields × usages). Threading: any. Memory: allocates the result.
HidReportDescriptor parseReportDescriptor(std::span<const uint8_t> bytes);

/// Where one value sits in a report (bits after the report ID byte), and its logical range.
/// bitSize 0: the report has no such field.
struct FieldLocation {
    uint32_t bitOffset = 0;
    uint32_t bitSize = 0;
    int64_t logicalMin = 0, logicalMax = 0;
    bool present() const noexcept { return bitSize != 0; }
};

/// How to select one usage: write `value` into `field`. An array field gets the usage's
/// selector; a one-bit variable field (one bit per usage) gets 1.
struct FieldChoice {
    FieldLocation field;
    int64_t value = 0;
    bool present() const noexcept { return field.present(); }
};

/// One report: its ID (0: unnumbered) and size in bytes with the ID byte. bytes 0: absent.
struct ReportLocation {
    uint8_t id = 0;
    uint32_t bytes = 0;
    bool present() const noexcept { return bytes != 0; }
};

/// The reports and fields a constant-force stream uses, found by findPidLayout(). Plain data;
/// fields marked optional may be absent (present() false), the rest are always present.
struct PidLayout {
    static constexpr std::size_t kMaxAxes = 8;
    static constexpr std::size_t kMaxButtons = 32;

    struct Axis {
        uint16_t usage = 0;  ///< Generic Desktop usage (desktop::kX, ...)
        FieldLocation field;
    };
    /// The joystick input report: axes in descriptor order (X, Y, ... up to kMaxAxes) and up to
    /// kMaxButtons buttons (consecutive one-bit fields on the Button page; buttonCount may be 0).
    ReportLocation input;
    std::array<Axis, kMaxAxes> axes{};
    std::size_t axisCount = 0;
    uint32_t buttonsBitOffset = 0;
    uint32_t buttonCount = 0;

    /// Set Effect (0x21), output.
    struct SetEffect {
        ReportLocation report;
        FieldLocation blockIndex;
        FieldChoice typeConstant;           ///< Effect Type = ET Constant Force
        FieldLocation duration, triggerRepeatInterval, samplePeriod, startDelay;  ///< optional
        FieldLocation gain, triggerButton;  ///< optional
        std::array<FieldLocation, 2> axisEnable{};  ///< optional: Axes Enable bits for X, Y
        FieldLocation directionEnable;      ///< optional
        std::array<FieldLocation, 2> direction{};   ///< optional: Direction, instances 1, 2
    } setEffect;

    /// Set Constant Force (0x73), output.
    struct ConstantForce {
        ReportLocation report;
        FieldLocation blockIndex, magnitude;
    } constantForce;

    /// Effect Operation (0x77), output.
    struct EffectOperation {
        ReportLocation report;
        FieldLocation blockIndex;
        FieldChoice start, stop;
        FieldLocation loopCount;  ///< optional
    } effectOperation;

    /// PID Device Control (0x96), output; disable, stop-all and reset optional.
    struct DeviceControl {
        ReportLocation report;
        FieldChoice enableActuators, disableActuators, stopAllEffects, reset;
    } deviceControl;

    /// Create New Effect (0xAB), feature; optional (absent: the host picks block indices).
    struct CreateNewEffect {
        ReportLocation report;
        FieldChoice typeConstant;
    } createNewEffect;

    /// PID Block Load (0x89), feature; present whenever createNewEffect is.
    struct BlockLoad {
        ReportLocation report;
        FieldLocation blockIndex;
        FieldChoice success;  ///< the Block Load Status value that means success
    } blockLoad;

    /// Device Gain (0x7D), output; optional.
    struct DeviceGain {
        ReportLocation report;
        FieldLocation gain;
    } deviceGain;
};

/// Finds the joystick input report and the PID reports above.
/// @throw HidDescriptorError when the descriptor has no PID usages at all ("not a
///        force-feedback device"), or lacks a required report or field (named in the message),
///        or has a report longer than `maxReportBytes`.
/// Complexity: O(fields × usages). Threading: any. Memory: none beyond the result.
PidLayout findPidLayout(const HidReportDescriptor& descriptor, std::size_t maxReportBytes = 64);

}  // namespace kizamu::haptics::hid
