// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import_ply.cpp
/// @brief The PLY reader: ASCII and binary (both byte orders), vertex colours, faces as fans.
///
/// Header lines it does not know are skipped with a warning; a count, an index or a value that
/// cannot be read is an error naming its line, or in binary data its entry and byte.
#include "mesh/mesh_import_text.h"

#include <optional>
#include <unordered_map>

namespace kizamu::mesh::detail {

namespace {


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

}  // namespace

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

}  // namespace kizamu::mesh::detail
