// SPDX-License-Identifier: Apache-2.0
/// @file figures.h
/// @brief Benchmark output: a readable table, or one JSON object per line (the contract).
///
/// `{"figure": "<area>.<name>", "value": <number>, "unit": "<unit>"}` per figure with --json
/// and nothing else on stdout (design brief); progress goes to stderr. Figure names are a
/// contract that scripts read: add freely, never rename.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace kizamu::bench {

class FigureSink {
public:
    explicit FigureSink(bool json, std::FILE* out = stdout) : mJson(json), mOut(out) {}
    /// Records and prints one figure. `note` is shown in the table only.
    void add(const std::string& name, double value, const std::string& unit, const std::string& note = "");
    /// Prints a section heading (table mode only).
    void section(const std::string& title);
    /// Progress line on stderr (both modes).
    void progress(const std::string& line);

    struct Figure {
        std::string name;
        double value;
        std::string unit;
    };
    const std::vector<Figure>& figures() const { return mFigures; }
    /// Value of a recorded figure, or NaN.
    double value(const std::string& name) const;

private:
    bool mJson;
    std::FILE* mOut;
    std::vector<Figure> mFigures;
};

}  // namespace kizamu::bench
