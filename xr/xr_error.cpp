// SPDX-License-Identifier: Apache-2.0
#include "xr/xr_error.h"

namespace kizamu::xr {

std::string resultName(XrInstance instance, XrResult result) {
    char name[XR_MAX_RESULT_STRING_SIZE] = {};
    if (instance != XR_NULL_HANDLE && XR_SUCCEEDED(xrResultToString(instance, result, name))) return name;
    return "XrResult " + std::to_string(int(result));
}

void check(XrInstance instance, XrResult result, const char* call) {
    if (XR_FAILED(result)) throw XrFailure(std::string(call) + ": " + resultName(instance, result), result);
}

}  // namespace kizamu::xr
