// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import_text.h
/// @brief What the mesh readers share (internal to src/mesh/mesh_import*): the warning log, the
/// line reader that names lines in errors, number parsing as other readers parse, and text
/// encodings (UTF-8 and UTF-16 with a byte-order mark).
#pragma once

#include "mesh/mesh_buffers.h"
#include "mesh/mesh_import.h"
#include "util/file_error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace kizamu::mesh::detail {

inline constexpr std::size_t kMaxWarningKinds = 16;    ///< distinct warnings kept per file
inline constexpr std::size_t kSniffBytes = 64 * 1024;  ///< how much recognition by content reads
inline constexpr std::size_t kTextProbeBytes = 512;    ///< how much decides text against binary

inline const char* formatName(MeshFormat f) {
    switch (f) {
        case MeshFormat::Obj:
            return "OBJ";
        case MeshFormat::Stl:
            return "STL";
        case MeshFormat::Ply:
            return "PLY";
        case MeshFormat::Off:
            return "OFF";
        case MeshFormat::Glb:
            return "glTF binary";
    }
    return "?";
}

/// `s` quoted for a one-line message: at most 40 bytes (whole UTF-8 characters), control
/// characters shown as '?'.
inline std::string quoted(std::string_view s) {
    std::size_t n = std::min<std::size_t>(s.size(), 40);
    if (n < s.size())
        while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
    std::string out = "'";
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        out += c < 0x20 || c == 0x7F ? '?' : char(c);
    }
    return out + (n < s.size() ? "...'" : "'");
}

/// A number for a message: whole numbers without decimals.
inline std::string number(double v) {
    if (std::isfinite(v) && v == std::trunc(v) && std::abs(v) < 1e15)
        return std::to_string((long long)v);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

/// The warnings of one file: each kind once, at its first occurrence, with a count of its
/// repeats, so a file with a million odd lines gives one warning and not a million.
class WarningLog {
public:
    /// `kind` groups repeats; `message()` is called for the first of a kind only.
    template <class MakeMessage>
    void add(std::string_view kind, MakeMessage&& message) {
        for (Entry& e : mEntries)
            if (e.kind == kind) {
                ++e.repeats;
                return;
            }
        if (mEntries.size() == kMaxWarningKinds) {
            ++mDropped;
            return;
        }
        mEntries.push_back({std::string(kind), std::string(message()), 0});
    }
    void appendTo(std::vector<std::string>* out, const std::string& name) const {
        if (out == nullptr) return;
        for (const Entry& e : mEntries)
            out->push_back(
                name + ": " + e.message +
                (e.repeats ? " (and " + std::to_string(e.repeats) + " more like it)" : ""));
        if (mDropped)
            out->push_back(name + ": " + std::to_string(mDropped) +
                           " more warnings of other kinds");
    }

private:
    struct Entry {
        std::string kind, message;
        std::size_t repeats;
    };
    std::vector<Entry> mEntries;
    std::size_t mDropped = 0;
};

/// Line-oriented reader for the text formats; lines end in LF, CRLF or CR. Errors and warnings
/// name the line.
class TextReader {
public:
    TextReader(std::string_view text, const std::string& name, WarningLog& log)
        : mText(text), mNextLf(std::min(text.find('\n'), text.size())), mName(name), mLog(log) {}

    /// Next line without its end, or false at the end of the text.
    /// Complexity: O(line length); the next LF is found once for all CR-only lines before it.
    bool nextLine(std::string_view& line) {
        if (mPos >= mText.size()) return false;
        if (mNextLf < mPos) mNextLf = std::min(mText.find('\n', mPos), mText.size());
        std::size_t end = mNextLf, next = mNextLf + 1;
        if (const void* cr = std::memchr(mText.data() + mPos, '\r', mNextLf - mPos)) {
            end = std::size_t(static_cast<const char*>(cr) - mText.data());
            next = end + 1 == mNextLf ? mNextLf + 1 : end + 1;  // CRLF, or a lone CR
        }
        line = mText.substr(mPos, end - mPos);
        mPos = next;
        ++mLine;
        return true;
    }
    [[noreturn]] void fail(const std::string& problem) const {
        throw FileError(mName, "line " + std::to_string(mLine) + ": " + problem);
    }
    /// A warning of `kind` at this line; `problem` is only built for the first of a kind.
    template <class MakeProblem>
    void warn(std::string_view kind, MakeProblem&& problem) {
        mLog.add(kind,
                 [&] { return "line " + std::to_string(mLine) + ": " + std::string(problem()); });
    }
    std::size_t bytesLeft() const { return mPos < mText.size() ? mText.size() - mPos : 0; }
    std::size_t offset() const { return std::min(mPos, mText.size()); }
    std::size_t lineNumber() const { return mLine; }

private:
    std::string_view mText;
    std::size_t mPos = 0;
    std::size_t mNextLf;  ///< position of the first '\n' at or after mPos, or the size
    std::size_t mLine = 0;
    const std::string& mName;
    WarningLog& mLog;
};

inline bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Splits `line` (up to a '#' comment) on blanks into `out`; returns how many tokens.
inline std::size_t split(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    line = line.substr(0, line.find('#'));
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isBlank(line[i])) ++i;
        if (i >= line.size()) break;
        const std::size_t start = i;
        while (i < line.size() && !isBlank(line[i])) ++i;
        out.push_back(line.substr(start, i - start));
    }
    return out.size();
}

inline bool equalsNoCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

/// True when the text, after leading blanks and line ends, starts with `word` in any case.
inline bool startsWithNoCase(std::string_view text, std::string_view word) {
    std::size_t i = 0;
    while (i < text.size() && (isBlank(text[i]) || text[i] == '\n')) ++i;
    return equalsNoCase(text.substr(i, word.size()), word);
}

inline bool containsNoCase(std::string_view text, std::string_view word) {
    return std::search(text.begin(), text.end(), word.begin(), word.end(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           }) != text.end();
}

/// No NUL byte in the first kTextProbeBytes: text, as far as binary STL and PLY data go (their
/// counts and coordinates all but always hold a zero byte).
inline bool looksLikeText(std::string_view bytes) {
    const std::size_t n = std::min(bytes.size(), kTextProbeBytes);
    return n == 0 || std::memchr(bytes.data(), '\0', n) == nullptr;
}

/// True when `v` is a whole number in [0, limit).
inline bool isIndex(double v, double limit) {
    return v >= 0.0 && v < limit && v == std::trunc(v);
}

/// `s` without one leading '+' before a digit or a point: `+1.5e-3` reads as strtod reads it,
/// which std::from_chars does not.
inline std::string_view withoutPlus(std::string_view s) {
    return s.size() > 1 && s[0] == '+' && s[1] != '+' && s[1] != '-' ? s.substr(1) : s;
}

inline bool parseFloat(std::string_view s, float& v) {
    s = withoutPlus(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size() && std::isfinite(v);
}
template <class Number>
inline bool parseNumber(std::string_view s, Number& v) {
    s = withoutPlus(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size();
}

/// Appends the fan of polygon `corners` as triangles.
inline void addPolygon(MeshBuffers& m, const uint32_t* corners, std::size_t n) {
    for (std::size_t k = 1; k + 1 < n; ++k)
        m.indices.insert(m.indices.end(), {corners[0], corners[k], corners[k + 1]});
}

// ---- Text encodings ----

inline void putUtf8(std::string& out, uint32_t c) {
    if (c < 0x80) {
        out += char(c);
    } else if (c < 0x800) {
        out += char(0xC0 | (c >> 6));
        out += char(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
        out += char(0xE0 | (c >> 12));
        out += char(0x80 | ((c >> 6) & 0x3F));
        out += char(0x80 | (c & 0x3F));
    } else {
        out += char(0xF0 | (c >> 18));
        out += char(0x80 | ((c >> 12) & 0x3F));
        out += char(0x80 | ((c >> 6) & 0x3F));
        out += char(0x80 | (c & 0x3F));
    }
}

inline bool hasUtf16Mark(std::string_view bytes) {
    return bytes.substr(0, 2) == "\xFF\xFE" || bytes.substr(0, 2) == "\xFE\xFF";
}

/// The text of `bytes` as UTF-8: without a UTF-8 byte-order mark, or, after a UTF-16 one (either
/// byte order), converted into `storage` (unpaired surrogates become U+FFFD). Only the first
/// `limit` bytes are converted. `transcoded` says whether `storage` holds the text.
inline std::string_view textOf(std::string_view bytes, std::string& storage, bool& transcoded,
                        WarningLog* log, std::size_t limit = std::string_view::npos) {
    transcoded = false;
    if (bytes.substr(0, 3) == "\xEF\xBB\xBF") return bytes.substr(3);
    if (!hasUtf16Mark(bytes)) return bytes;
    transcoded = true;
    const bool little = bytes[0] == '\xFF';
    const std::size_t size = std::min(bytes.size(), limit);
    const std::size_t units = (size - 2) / 2;
    if (log != nullptr && size == bytes.size() && (size - 2) % 2 != 0)
        log->add("utf16-odd", [] {
            return "UTF-16 text with an odd number of bytes: the last byte is ignored";
        });
    const auto* u = reinterpret_cast<const unsigned char*>(bytes.data()) + 2;
    auto unit = [&](std::size_t k) -> uint32_t {
        return little ? (uint32_t(u[2 * k + 1]) << 8) | u[2 * k]
                      : (uint32_t(u[2 * k]) << 8) | u[2 * k + 1];
    };
    storage.clear();
    storage.reserve(units);
    for (std::size_t k = 0; k < units; ++k) {
        uint32_t c = unit(k);
        if (c >= 0xD800 && c < 0xDC00 && k + 1 < units && unit(k + 1) >= 0xDC00 &&
            unit(k + 1) < 0xE000) {
            c = 0x10000 + ((c - 0xD800) << 10) + (unit(k + 1) - 0xDC00);
            ++k;
        } else if (c >= 0xD800 && c < 0xE000) {
            c = 0xFFFD;
        }
        putUtf8(storage, c);
    }
    return storage;
}


/// Reads a PLY file (ASCII or binary); `transcoded`: its header was UTF-16, so `bytes` are a
/// converted copy (mesh_import_ply.cpp).
MeshBuffers readPly(std::string_view bytes, const std::string& name, WarningLog& log, bool transcoded);

}  // namespace kizamu::mesh::detail
