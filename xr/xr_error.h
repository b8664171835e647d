// SPDX-License-Identifier: Apache-2.0
/// @file xr_error.h
/// @brief OpenXR results as exceptions: a failed call becomes an XrFailure whose message names
/// the call and the runtime's name for the result ("xrCreateSession: XR_ERROR_FORM_FACTOR_UNAVAILABLE").
///
/// Setup code (instance, session, swapchains, actions) throws; the frame loop checks results
/// whose failure ends the session (XR_ERROR_SESSION_LOST) and carries on past those a frame can
/// drop. Threading: any.
#pragma once

#include <openxr/openxr.h>

#include <stdexcept>
#include <string>

namespace kizamu::xr {

class XrFailure : public std::runtime_error {
public:
    XrFailure(const std::string& what, XrResult result) : std::runtime_error(what), mResult(result) {}
    XrResult result() const noexcept { return mResult; }

private:
    XrResult mResult;
};

/// The result's name ("XR_ERROR_HANDLE_INVALID"); the runtime's own name where `instance` is
/// live, else the number.
std::string resultName(XrInstance instance, XrResult result);

/// Throws XrFailure("call: RESULT_NAME") when `result` is a failure (XR_FAILED).
void check(XrInstance instance, XrResult result, const char* call);

}  // namespace kizamu::xr
