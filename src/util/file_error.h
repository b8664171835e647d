// SPDX-License-Identifier: Apache-2.0
/// @file file_error.h
/// @brief The one exception type file readers and writers throw: a one-line, user-facing message.
///
/// Cold paths only (loading, saving). The message names the file and the problem, e.g.
/// "part.kza: truncated: tile 12 of 40 ends past the end of the file". Never crosses a thread
/// entry point: the app catches it where it started the operation.
#pragma once

#include <stdexcept>
#include <string>

namespace kizamu {

class FileError : public std::runtime_error {
public:
    FileError(const std::string& path, const std::string& problem)
        : std::runtime_error(path + ": " + problem) {}
};

}  // namespace kizamu
