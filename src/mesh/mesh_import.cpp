// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import.cpp
/// @brief OBJ, STL, PLY and OFF readers, and recognition of a format by content.
///
/// Leniency follows what assimp, MeshLab and tinyobjloader accept: unknown statements and
/// header lines are stepped over with a warning; a count, an index or a coordinate that cannot
/// be read is an error naming its line (or, in binary data, its entry and byte).
#include "mesh/mesh_import.h"

#include "util/atomic_file.h"
#include "util/file_error.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <unordered_map>
#include <vector>

namespace kizamu::mesh {

namespace {

constexpr std::size_t kMaxWarningKinds = 16;    ///< distinct warnings kept per file
constexpr std::size_t kSniffBytes = 64 * 1024;  ///< how much recognition by content reads
constexpr std::size_t kTextProbeBytes = 512;    ///< how much decides text against binary

const char* formatName(MeshFormat f) {
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
std::string quoted(std::string_view s) {
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
std::string number(double v) {
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

bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Splits `line` (up to a '#' comment) on blanks into `out`; returns how many tokens.
std::size_t split(std::string_view line, std::vector<std::string_view>& out) {
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

bool equalsNoCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

/// True when the text, after leading blanks and line ends, starts with `word` in any case.
bool startsWithNoCase(std::string_view text, std::string_view word) {
    std::size_t i = 0;
    while (i < text.size() && (isBlank(text[i]) || text[i] == '\n')) ++i;
    return equalsNoCase(text.substr(i, word.size()), word);
}

bool containsNoCase(std::string_view text, std::string_view word) {
    return std::search(text.begin(), text.end(), word.begin(), word.end(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           }) != text.end();
}

/// No NUL byte in the first kTextProbeBytes: text, as far as binary STL and PLY data go (their
/// counts and coordinates all but always hold a zero byte).
bool looksLikeText(std::string_view bytes) {
    const std::size_t n = std::min(bytes.size(), kTextProbeBytes);
    return n == 0 || std::memchr(bytes.data(), '\0', n) == nullptr;
}

/// True when `v` is a whole number in [0, limit).
bool isIndex(double v, double limit) {
    return v >= 0.0 && v < limit && v == std::trunc(v);
}

/// `s` without one leading '+' before a digit or a point: `+1.5e-3` reads as strtod reads it,
/// which std::from_chars does not.
std::string_view withoutPlus(std::string_view s) {
    return s.size() > 1 && s[0] == '+' && s[1] != '+' && s[1] != '-' ? s.substr(1) : s;
}

bool parseFloat(std::string_view s, float& v) {
    s = withoutPlus(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size() && std::isfinite(v);
}
template <class Number>
bool parseNumber(std::string_view s, Number& v) {
    s = withoutPlus(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size();
}

/// Appends the fan of polygon `corners` as triangles.
void addPolygon(MeshBuffers& m, const uint32_t* corners, std::size_t n) {
    for (std::size_t k = 1; k + 1 < n; ++k)
        m.indices.insert(m.indices.end(), {corners[0], corners[k], corners[k + 1]});
}

// ---- Text encodings ----

void putUtf8(std::string& out, uint32_t c) {
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

bool hasUtf16Mark(std::string_view bytes) {
    return bytes.substr(0, 2) == "\xFF\xFE" || bytes.substr(0, 2) == "\xFE\xFF";
}

/// The text of `bytes` as UTF-8: without a UTF-8 byte-order mark, or, after a UTF-16 one (either
/// byte order), converted into `storage` (unpaired surrogates become U+FFFD). Only the first
/// `limit` bytes are converted. `transcoded` says whether `storage` holds the text.
std::string_view textOf(std::string_view bytes, std::string& storage, bool& transcoded,
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

// ---- OBJ ----

/// OBJ statements that hold nothing a triangle mesh needs (texture coordinates, normals, groups,
/// materials, lines, points, free-form geometry, display attributes).
bool isOtherObjStatement(std::string_view k) {
    static constexpr std::string_view kKnown[] = {
        "vt",        "vn",    "vp",       "g",        "o",    "s",      "usemtl", "mtllib",
        "l",         "p",     "cstype",   "deg",      "bmat", "step",   "curv",   "curv2",
        "surf",      "parm",  "trim",     "hole",     "scrv", "sp",     "end",    "con",
        "mg",        "bevel", "c_interp", "d_interp", "lod",  "usemap", "maplib", "shadow_obj",
        "trace_obj", "ctech", "stech",    "call",     "csh",  "res"};
    return std::find(std::begin(kKnown), std::end(kKnown), k) != std::end(kKnown);
}

MeshBuffers readObj(std::string_view text, const std::string& name, WarningLog& log) {
    TextReader r(text, name, log);
    MeshBuffers m;
    std::string_view line;
    std::vector<std::string_view> tok;
    std::vector<uint32_t> face;
    bool colours = true;
    while (r.nextLine(line)) {
        const std::size_t n = split(line, tok);
        if (n == 0) continue;
        if (tok[0] == "v") {
            if (n < 4) r.fail("a vertex needs 3 coordinates");
            glm::vec3 p, c(0.0f);
            for (int a = 0; a < 3; ++a)
                if (!parseFloat(tok[1 + a], p[a]))
                    r.fail("bad vertex coordinate " + quoted(tok[1 + a]));
            bool hasColour = n >= 7;
            for (int a = 0; a < 3 && hasColour; ++a)
                if (!parseFloat(tok[4 + a], c[a])) {
                    hasColour = false;
                    r.warn("obj-colour",
                           [&] { return "a vertex colour that is not a number is ignored"; });
                }
            // x y z, x y z w (w ignored, as every reader does) or x y z r g b; more are ignored.
            if (n == 6 || n > 7)
                r.warn("obj-values", [&] {
                    return "a vertex with " + std::to_string(n - 1) +
                           " values: the extra ones are ignored";
                });
            colours = colours && hasColour;
            m.positions.push_back(p);
            m.colours.push_back(glm::u8vec3(glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f));
        } else if (tok[0] == "f" || tok[0] == "fo") {  // fo: the old name of f
            if (n < 4) {
                r.warn("obj-face", [] { return "a face with fewer than 3 corners is skipped"; });
                continue;
            }
            face.clear();
            for (std::size_t k = 1; k < n; ++k) {
                const std::string_view idx = tok[k].substr(0, tok[k].find('/'));
                long long i;
                if (!parseNumber(idx, i) || i == 0) r.fail("bad face index " + quoted(tok[k]));
                const long long count = (long long)m.positions.size();
                const long long zeroBased =
                    i > 0 ? i - 1 : count + i;  // negative: relative to the end
                if (zeroBased < 0 || zeroBased >= count)
                    r.fail("face index " + std::to_string(i) + " out of range");
                face.push_back(uint32_t(zeroBased));
            }
            addPolygon(m, face.data(), face.size());
        } else if (!isOtherObjStatement(tok[0])) {
            r.warn("obj-statement " + std::string(tok[0].substr(0, 40)),
                   [&] { return "unknown statement " + quoted(tok[0]) + " skipped"; });
        }
    }
    if (!colours) m.colours.clear();
    return m;
}

// ---- STL ----

/// Welds exactly equal positions (STL stores three per facet).
struct Welder {
    MeshBuffers& m;
    std::unordered_map<uint64_t, std::vector<uint32_t>> buckets;
    uint32_t add(glm::vec3 p) {
        p += glm::vec3(0.0f);  // -0 becomes +0, so equal positions hash equally
        uint32_t bits[3];
        std::memcpy(bits, &p, 12);
        const uint64_t key =
            (uint64_t(bits[0]) * 0x9e3779b97f4a7c15ull) ^ (uint64_t(bits[1]) << 21) ^ bits[2];
        auto& bucket = buckets[key];
        for (uint32_t i : bucket)
            if (m.positions[i] == p) return i;
        m.positions.push_back(p);
        bucket.push_back(uint32_t(m.positions.size() - 1));
        return bucket.back();
    }
};

/// The facet count of a binary STL whose size is exactly 84 + 50 x the count in its header.
std::optional<uint32_t> exactBinaryStlCount(std::string_view bytes) {
    if (bytes.size() < 84) return std::nullopt;
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (84 + uint64_t(count) * 50 != bytes.size()) return std::nullopt;
    return count;
}

MeshBuffers readBinaryStl(std::string_view bytes, uint32_t count, const std::string& name) {
    MeshBuffers m;
    Welder weld{m, {}};
    for (uint32_t t = 0; t < count; ++t) {
        const std::size_t at = 84 + std::size_t(t) * 50;
        uint32_t tri[3];
        for (int k = 0; k < 3; ++k) {
            glm::vec3 p;
            std::memcpy(&p, bytes.data() + at + 12 + 12 * k, 12);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw FileError(name, "facet " + std::to_string(t) + " (byte " +
                                          std::to_string(at) + ") has a non-finite vertex");
            tri[k] = weld.add(p);
        }
        addPolygon(m, tri, 3);
    }
    return m;
}

MeshBuffers readAsciiStl(std::string_view text, const std::string& name, WarningLog& log) {
    MeshBuffers m;
    Welder weld{m, {}};
    TextReader r(text, name, log);
    std::string_view line;
    std::vector<std::string_view> tok;
    std::vector<uint32_t> facet;
    // A facet ends at endloop; endfacet, the next facet or endsolid end one whose endloop is
    // missing.
    auto closeFacet = [&] {
        if (facet.empty()) return;
        if (facet.size() < 3) {
            r.warn("stl-short", [] { return "a facet with fewer than 3 vertices is skipped"; });
        } else {
            if (facet.size() > 3)
                r.warn("stl-long", [&] {
                    return "a facet with " + std::to_string(facet.size()) +
                           " vertices is fanned into triangles";
                });
            addPolygon(m, facet.data(), facet.size());
        }
        facet.clear();
    };
    while (r.nextLine(line)) {
        const std::size_t n = split(line, tok);
        if (n == 0) continue;
        const std::string_view k = tok[0];
        if (equalsNoCase(k, "vertex")) {
            if (n < 4) r.fail("a vertex needs 3 coordinates");
            glm::vec3 p;
            for (int a = 0; a < 3; ++a)
                if (!parseFloat(tok[1 + a], p[a]))
                    r.fail("bad vertex coordinate " + quoted(tok[1 + a]));
            if (n > 4)
                r.warn("stl-values",
                       [] { return "values after a vertex's 3 coordinates are ignored"; });
            facet.push_back(weld.add(p));
        } else if (equalsNoCase(k, "endloop") || equalsNoCase(k, "endfacet") ||
                   equalsNoCase(k, "facet") || equalsNoCase(k, "endsolid")) {
            closeFacet();
        } else if (!equalsNoCase(k, "solid") && !equalsNoCase(k, "outer")) {
            r.warn("stl-line " + std::string(k.substr(0, 40)),
                   [&] { return "unknown line " + quoted(k) + " skipped"; });
        }
    }
    if (!facet.empty()) r.fail("truncated: the last facet is incomplete");
    return m;
}

MeshBuffers readStl(std::string_view bytes, const std::string& name, WarningLog& log) {
    if (const auto count = exactBinaryStlCount(bytes)) return readBinaryStl(bytes, *count, name);
    if (hasUtf16Mark(bytes) || looksLikeText(bytes)) {
        std::string storage;
        bool transcoded;
        const std::string_view text = textOf(bytes, storage, transcoded, &log);
        if (!startsWithNoCase(text, "solid")) {
            if (!containsNoCase(text.substr(0, kSniffBytes), "facet"))
                throw FileError(
                    name, "not an STL file (no 'solid' header, and not the size of a binary STL)");
            log.add("stl-solid", [] { return "no 'solid' header: read as ASCII STL"; });
        }
        return readAsciiStl(text, name, log);
    }
    if (bytes.size() < 84)
        throw FileError(name, "not an STL file (too short, and no 'solid' header)");
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    const uint64_t held = (bytes.size() - 84) / 50;
    if (count == 0 && held > 0) {
        // Some exporters leave the count at 0; the size says how many facets there are.
        count = uint32_t(std::min<uint64_t>(held, 0xFFFFFFFFu));
        log.add("stl-count", [&] {
            return "the header counts 0 facets; the " + std::to_string(count) +
                   " the file holds are read";
        });
    }
    if (count > held)
        throw FileError(name, "binary STL size does not match its facet count: it counts " +
                                  std::to_string(count) + " facets and holds " +
                                  std::to_string(held) + " (truncated?)");
    if (const uint64_t tail = bytes.size() - 84 - uint64_t(count) * 50; tail > 0)
        log.add("stl-tail", [&] {
            return std::to_string(tail) + " bytes after the last of " + std::to_string(count) +
                   " facets are ignored";
        });
    return readBinaryStl(bytes, count, name);
}

// ---- PLY ----

struct PlyProperty {
    std::string name;
    int type = 0;  ///< bytes of the scalar (or of the list items); negative for float types
    bool isSigned = false;
    bool list = false;
    int countType = 0;  ///< bytes of the list count
};
struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> props;
    std::size_t line = 0;  ///< of its `element` line
};

/// Size in bytes of a PLY scalar type; floats are returned negative. 0 if unknown.
int plyType(std::string_view t, bool& isSigned) {
    isSigned =
        t == "char" || t == "short" || t == "int" || t == "int8" || t == "int16" || t == "int32";
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32") return 4;
    if (t == "float" || t == "float32") return -4;
    if (t == "double" || t == "float64") return -8;
    return 0;
}

/// Reads PLY values in ASCII or binary of either byte order, bounds-checked. A read that fails
/// returns false and leaves the reason in problem(); the caller says where.
class PlyValues {
public:
    PlyValues(std::string_view body, int format, std::size_t firstLine)
        : mBody(body), mFormat(format), mLine(firstLine) {}
    bool read(int type, bool isSigned, double& v) {
        if (mFormat == 0) return readText(v);
        const std::size_t n = std::size_t(std::abs(type));
        if (n > mBody.size() - mPos) {
            mProblem = "truncated: the data ends early";
            return false;
        }
        unsigned char b[8];
        std::memcpy(b, mBody.data() + mPos, n);
        mPos += n;
        if (mFormat == 2) std::reverse(b, b + n);  // big-endian file on a little-endian host
        switch (type) {
            case 1:
                v = isSigned ? double(int8_t(b[0])) : double(b[0]);
                break;
            case 2: {
                uint16_t x;
                std::memcpy(&x, b, 2);
                v = isSigned ? double(int16_t(x)) : double(x);
                break;
            }
            case 4: {
                uint32_t x;
                std::memcpy(&x, b, 4);
                v = isSigned ? double(int32_t(x)) : double(x);
                break;
            }
            case -4: {
                float x;
                std::memcpy(&x, b, 4);
                v = double(x);
                break;
            }
            default:
                std::memcpy(&v, b, 8);
                break;
        }
        return true;
    }
    std::size_t bytesLeft() const { return mBody.size() - mPos; }
    std::size_t offset() const { return mPos; }
    std::size_t line() const { return mLine; }  ///< ASCII: the line of the last value read
    const std::string& problem() const { return mProblem; }

private:
    bool readText(double& v) {
        const std::size_t lastLine = mLine;
        for (; mPos < mBody.size() && std::isspace(static_cast<unsigned char>(mBody[mPos]));
             ++mPos) {
            const bool crAlone =
                mBody[mPos] == '\r' && (mPos + 1 == mBody.size() || mBody[mPos + 1] != '\n');
            if (mBody[mPos] == '\n' || crAlone) ++mLine;
        }
        const std::size_t start = mPos;
        while (mPos < mBody.size() && !std::isspace(static_cast<unsigned char>(mBody[mPos])))
            ++mPos;
        if (start == mPos) {
            mLine = lastLine;  // the data ended on the line of the last value
            mProblem = "truncated: the data ends early";
            return false;
        }
        const std::string_view token = mBody.substr(start, mPos - start);
        if (!parseNumber(token, v)) {
            mProblem = "bad number " + quoted(token);
            return false;
        }
        return true;
    }
    std::string_view mBody;
    std::size_t mPos = 0;
    int mFormat;  ///< 0 ascii, 1 little-endian, 2 big-endian
    std::size_t mLine;
    std::string mProblem;
};

uint8_t colourByte(double v) {
    return std::isfinite(v) ? uint8_t(std::clamp(v, 0.0, 255.0)) : 0;
}

/// `transcoded`: the header was UTF-16, so `bytes` are a converted copy (binary data is lost).
MeshBuffers readPly(std::string_view bytes, const std::string& name, WarningLog& log,
                    bool transcoded) {
    if (bytes.substr(0, 3) != "ply") throw FileError(name, "not a PLY file (no 'ply' magic)");
    TextReader r(bytes, name, log);
    std::string_view line;
    std::vector<std::string_view> tok;
    int format = -1;
    std::vector<PlyElement> elements;
    bool ended = false;
    r.nextLine(line);
    while (!ended && r.nextLine(line)) {
        const std::size_t n = split(line, tok);
        if (n == 0 || tok[0] == "comment" || tok[0] == "obj_info") continue;
        if (tok[0] == "format") {
            if (n < 2) r.fail("format needs a value");
            format = tok[1] == "ascii"                  ? 0
                     : tok[1] == "binary_little_endian" ? 1
                     : tok[1] == "binary_big_endian"    ? 2
                                                        : -1;
            if (format < 0) r.fail("unknown PLY format " + quoted(tok[1]));
        } else if (tok[0] == "element") {
            PlyElement e;
            if (n != 3 || !parseNumber(tok[2], e.count))
                r.fail("an element needs a name and a count");
            e.name = std::string(tok[1]);
            e.line = r.lineNumber();
            for (const PlyElement& other : elements)
                if (other.name == e.name) r.fail("element " + quoted(e.name) + " appears twice");
            elements.push_back(e);
        } else if (tok[0] == "property") {
            if (elements.empty()) r.fail("a property before any element");
            PlyProperty p;
            if (n == 5 && tok[1] == "list") {
                bool countSigned;
                p.list = true;
                p.countType = plyType(tok[2], countSigned);
                p.type = plyType(tok[3], p.isSigned);
                p.name = std::string(tok[4]);
                if (p.countType <= 0 || p.type == 0) r.fail("bad list property types");
            } else if (n == 3) {
                p.type = plyType(tok[1], p.isSigned);
                p.name = std::string(tok[2]);
                if (p.type == 0) r.fail("unknown property type " + quoted(tok[1]));
            } else {
                r.fail("malformed property line");
            }
            elements.back().props.push_back(p);
        } else if (tok[0] == "end_header") {
            ended = true;
        } else {
            // Old Blender exporters wrote a bare "Created by ..." line; readers step over it.
            r.warn("ply-header " + std::string(tok[0].substr(0, 40)), [&] {
                return "header line " + quoted(line) + " is not a PLY keyword; skipped";
            });
        }
    }
    if (!ended) throw FileError(name, "truncated: no end_header");
    if (format < 0) throw FileError(name, "the header has no format line");
    if (format != 0 && transcoded)
        throw FileError(name, "a binary PLY with a UTF-16 header cannot be read");

    const std::size_t bodyStart = r.offset();
    PlyValues values(bytes.substr(bodyStart), format, r.lineNumber() + 1);
    const PlyElement* e = nullptr;
    uint64_t i = 0;
    // Where the value just read is: its line (ASCII) or byte (binary), and its entry.
    auto at = [&](const std::string& problem) {
        const std::string entry =
            e->name + " " + std::to_string(i) + " of " + std::to_string(e->count);
        return format == 0
                   ? "line " + std::to_string(values.line()) + ": " + problem + " (" + entry + ")"
                   : entry + ", byte " + std::to_string(bodyStart + values.offset()) + ": " +
                         problem;
    };
    auto next = [&](int type, bool isSigned) {
        double v;
        if (!values.read(type, isSigned, v)) throw FileError(name, at(values.problem()));
        return v;
    };
    MeshBuffers m;
    bool haveColours = false;
    std::vector<uint32_t> face;
    for (const PlyElement& element : elements) {
        e = &element;
        const std::string declared =
            "line " + std::to_string(e->line) + ": element " + quoted(e->name);
        // Every value takes at least one byte (binary) or two characters (ASCII), so an entry
        // takes at least as many bytes as it has properties: bound the count before reading.
        if (e->props.empty() && e->count > 0)
            throw FileError(name, declared + " has entries but no properties");
        if (e->count > values.bytesLeft() / std::max<std::size_t>(1, e->props.size()))
            throw FileError(name, declared + " claims more entries than the file holds");
        const bool isVertex = e->name == "vertex", isFace = e->name == "face";
        if (isVertex) {
            m.positions.reserve(std::size_t(e->count));
            haveColours = std::any_of(e->props.begin(), e->props.end(),
                                      [](const PlyProperty& p) { return p.name == "red"; });
        }
        for (i = 0; i < e->count; ++i) {
            glm::vec3 p(0.0f);
            glm::u8vec3 c(0);
            for (const PlyProperty& prop : e->props) {
                if (prop.list) {
                    const double count = next(prop.countType, false);
                    if (!isIndex(count, 1e6))
                        throw FileError(name, at("a list of " + number(count) + " items"));
                    const bool isCorners =
                        isFace && (prop.name == "vertex_indices" || prop.name == "vertex_index");
                    face.clear();
                    for (int k = 0; k < int(count); ++k) {
                        const double v = next(prop.type, prop.isSigned);
                        if (!isCorners) continue;
                        if (!isIndex(v, double(m.positions.size())))
                            throw FileError(name,
                                            at("vertex index " + number(v) + " out of range (" +
                                               std::to_string(m.positions.size()) + " vertices)"));
                        face.push_back(uint32_t(v));
                    }
                    if (isCorners && face.size() < 3)
                        log.add("ply-face",
                                [&] { return at("a face with fewer than 3 corners is skipped"); });
                    else if (isCorners)
                        addPolygon(m, face.data(), face.size());
                    continue;
                }
                const double v = next(prop.type, prop.isSigned);
                if (!isVertex) continue;
                const double colourScale = prop.type < 0 ? 255.0 : 1.0;  // float colours are 0..1
                if (prop.name == "x")
                    p.x = float(v);
                else if (prop.name == "y")
                    p.y = float(v);
                else if (prop.name == "z")
                    p.z = float(v);
                else if (prop.name == "red")
                    c.r = colourByte(v * colourScale);
                else if (prop.name == "green")
                    c.g = colourByte(v * colourScale);
                else if (prop.name == "blue")
                    c.b = colourByte(v * colourScale);
            }
            if (isVertex) {
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    throw FileError(name, at("the vertex is not finite"));
                m.positions.push_back(p);
                if (haveColours) m.colours.push_back(c);
            }
        }
    }
    return m;
}

// ---- OFF ----

/// True for the header keywords of 3D OFF: [ST][C][N]OFF.
bool isOffKeyword(std::string_view k) {
    if (k.substr(0, 2) == "ST") k.remove_prefix(2);
    if (!k.empty() && k[0] == 'C') k.remove_prefix(1);
    if (!k.empty() && k[0] == 'N') k.remove_prefix(1);
    return k == "OFF";
}

bool endsWithOff(std::string_view k) {
    return k.size() >= 3 && k.substr(k.size() - 3) == "OFF";
}

MeshBuffers readOff(std::string_view text, const std::string& name, WarningLog& log) {
    TextReader r(text, name, log);
    std::string_view line;
    std::vector<std::string_view> tok;
    auto next = [&]() -> std::size_t {
        while (r.nextLine(line)) {
            const std::size_t n = split(line, tok);
            if (n > 0) return n;
        }
        r.fail("truncated: the file ends early");
    };
    std::size_t n = next();
    std::size_t at = 0;  // where the counts start on the current line
    uint64_t nv, nf;
    if (endsWithOff(tok[0])) {
        if (!isOffKeyword(tok[0]))
            r.fail("the OFF variant " + quoted(tok[0]) + " (not 3D) cannot be read");
        if (n >= 2 && tok[1] == "BINARY") r.fail("binary OFF cannot be read");
        at = 1;  // the counts may follow the keyword on the same line
        if (n == 1) {
            n = next();
            at = 0;
        }
    } else if (parseNumber(tok[0], nv)) {
        r.warn("off-header", [] {
            return "no OFF header keyword (it is optional): the counts are read from here";
        });
    } else {
        r.fail("not an OFF file (no OFF header)");
    }
    if (n < at + 2 || !parseNumber(tok[at], nv) || !parseNumber(tok[at + 1], nf))
        r.fail("expected vertex and face counts");
    if (nv > r.bytesLeft() || nf > r.bytesLeft()) r.fail("counts exceed the size of the file");
    MeshBuffers m;
    m.positions.reserve(std::size_t(nv));
    for (uint64_t i = 0; i < nv; ++i) {
        if (next() < 3) r.fail("a vertex needs 3 coordinates");
        glm::vec3 p;
        for (int a = 0; a < 3; ++a)
            if (!parseFloat(tok[a], p[a])) r.fail("bad vertex coordinate " + quoted(tok[a]));
        m.positions.push_back(p);
    }
    std::vector<uint32_t> face;
    for (uint64_t f = 0; f < nf; ++f) {
        const std::size_t k = next();
        std::size_t count;
        if (!parseNumber(tok[0], count))
            r.fail("a face needs a vertex count, not " + quoted(tok[0]));
        if (count > k - 1)
            r.fail("a face of " + std::to_string(count) + " corners lists " +
                   std::to_string(k - 1));
        if (count < 3) {
            r.warn("off-face", [] { return "a face with fewer than 3 corners is skipped"; });
            continue;
        }
        face.clear();
        for (std::size_t j = 0; j < count; ++j) {
            uint32_t i;
            if (!parseNumber(tok[1 + j], i) || i >= m.positions.size())
                r.fail("face index " + quoted(tok[1 + j]) + " out of range (" +
                       std::to_string(m.positions.size()) + " vertices)");
            face.push_back(i);
        }
        addPolygon(m, face.data(), face.size());
    }
    return m;
}

/// True when the lines of `text` read as OBJ: a `v` line, and at least as many OBJ statements
/// (v, f and the rest) as other lines.
bool looksLikeObj(std::string_view text) {
    WarningLog ignored;
    const std::string noName;
    TextReader r(text, noName, ignored);
    std::string_view line;
    std::vector<std::string_view> tok;
    std::size_t vertices = 0, statements = 0, others = 0;
    while (r.nextLine(line)) {
        if (split(line, tok) == 0) continue;
        if (tok[0] == "v") ++vertices;
        if (tok[0] == "v" || tok[0] == "f" || isOtherObjStatement(tok[0]))
            ++statements;
        else
            ++others;
    }
    return vertices > 0 && statements >= others;
}

}  // namespace

std::optional<MeshFormat> meshFormatOfContent(std::string_view bytes) {
    if (bytes.empty()) return std::nullopt;
    if (bytes.substr(0, 4) == "glTF") return MeshFormat::Glb;
    std::string storage;
    bool transcoded;
    const std::string_view head =
        textOf(bytes, storage, transcoded, nullptr, kSniffBytes).substr(0, kSniffBytes);
    if (head.size() > 3 && head.substr(0, 3) == "ply" && (head[3] == '\n' || head[3] == '\r'))
        return MeshFormat::Ply;
    if (!transcoded && exactBinaryStlCount(bytes)) return MeshFormat::Stl;
    if (!looksLikeText(head)) return std::nullopt;
    {
        WarningLog ignored;
        const std::string noName;
        TextReader r(head, noName, ignored);
        std::string_view line;
        std::vector<std::string_view> tok;
        while (r.nextLine(line))
            if (split(line, tok) > 0) break;
        if (!tok.empty() && endsWithOff(tok[0])) return MeshFormat::Off;
    }
    if (startsWithNoCase(head, "solid") && containsNoCase(head, "facet")) return MeshFormat::Stl;
    if (looksLikeObj(head)) return MeshFormat::Obj;
    return std::nullopt;
}

MeshBuffers decodeMesh(std::string_view bytes, MeshFormat format, const std::string& name,
                       std::vector<std::string>* warnings) {
    if (bytes.empty()) throw FileError(name, "the file is empty");
    WarningLog log;
    std::string storage;
    bool transcoded = false;
    MeshBuffers m;
    switch (format) {
        case MeshFormat::Obj:
            m = readObj(textOf(bytes, storage, transcoded, &log), name, log);
            break;
        case MeshFormat::Stl:
            m = readStl(bytes, name, log);
            break;  // binary or text: it decides
        case MeshFormat::Ply: {
            const std::string_view text = textOf(bytes, storage, transcoded, &log);
            m = readPly(text, name, log, transcoded);
            break;
        }
        case MeshFormat::Off:
            m = readOff(textOf(bytes, storage, transcoded, &log), name, log);
            break;
        case MeshFormat::Glb:
            throw FileError(name, "reading .glb is not supported (use .obj, .stl, .ply or .off)");
    }
    if (m.triangleCount() == 0) throw FileError(name, "the file holds no triangles");
    log.appendTo(warnings, name);
    return m;
}

MeshBuffers importMesh(const std::string& path, std::vector<std::string>* warnings) {
    const std::string bytes = util::readWholeFile(path);
    std::optional<MeshFormat> byName;
    try {
        byName = meshFormatOf(path);
    } catch (const FileError&) {
        // Not a mesh extension: the content decides.
    }
    const std::optional<MeshFormat> byContent = meshFormatOfContent(bytes);
    if (!byName && !byContent)
        throw FileError(
            path,
            "unknown mesh format: neither the extension nor the content is OBJ, STL, PLY or OFF");
    if (byContent && byContent != byName && warnings != nullptr) {
        const std::string content = formatName(*byContent);
        warnings->push_back(path + ": " +
                            (byName ? "the extension names " + std::string(formatName(*byName))
                                    : "no mesh extension") +
                            ", but the content is " + content + ": read as " + content);
    }
    return decodeMesh(bytes, byContent.value_or(byName.value_or(MeshFormat::Obj)), path, warnings);
}

}  // namespace kizamu::mesh
