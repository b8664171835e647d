// SPDX-License-Identifier: Apache-2.0
/// @file mesh_import.cpp
/// @brief OBJ, STL, PLY and OFF readers.
#include "mesh/mesh_import.h"

#include "util/atomic_file.h"
#include "util/file_error.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace kizamu::mesh {

namespace {

/// Line-oriented tokenizer for the text formats; errors name the line.
class TextReader {
public:
    TextReader(std::string_view text, const std::string& name) : mText(text), mName(name) {}

    /// Next line without its end, or false at the end of the text.
    bool nextLine(std::string_view& line) {
        if (mPos >= mText.size()) return false;
        const std::size_t end = std::min(mText.find('\n', mPos), mText.size());
        line = mText.substr(mPos, end - mPos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        mPos = end + 1;
        ++mLine;
        return true;
    }
    [[noreturn]] void fail(const std::string& problem) const {
        throw FileError(mName, "line " + std::to_string(mLine) + ": " + problem);
    }
    std::size_t bytesLeft() const { return mPos < mText.size() ? mText.size() - mPos : 0; }
    std::size_t offset() const { return std::min(mPos, mText.size()); }

private:
    std::string_view mText;
    std::size_t mPos = 0;
    std::size_t mLine = 0;
    const std::string& mName;
};

/// Splits `line` (up to a '#' comment) on blanks into `out`; returns how many tokens.
std::size_t split(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    line = line.substr(0, line.find('#'));
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        if (i >= line.size()) break;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        out.push_back(line.substr(start, i - start));
    }
    return out.size();
}

/// True when `v` is a whole number in [0, limit).
bool isIndex(double v, double limit) { return v >= 0.0 && v < limit && v == std::trunc(v); }

bool parseFloat(std::string_view s, float& v) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size() && std::isfinite(v);
}
template <class Int>
bool parseInt(std::string_view s, Int& v) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size();
}

/// Appends the fan of polygon `corners` as triangles.
void addPolygon(MeshBuffers& m, const uint32_t* corners, std::size_t n) {
    for (std::size_t k = 1; k + 1 < n; ++k) m.indices.insert(m.indices.end(), {corners[0], corners[k], corners[k + 1]});
}

MeshBuffers readObj(std::string_view text, const std::string& name) {
    TextReader r(text, name);
    MeshBuffers m;
    std::string_view line;
    std::vector<std::string_view> tok;
    std::vector<uint32_t> face;
    bool colours = true;
    while (r.nextLine(line)) {
        const std::size_t n = split(line, tok);
        if (n == 0) continue;
        if (tok[0] == "v") {
            glm::vec3 p, c(0.0f);
            if (n != 4 && n != 5 && n != 7) r.fail("a vertex needs 3 coordinates (and an optional w, or a colour)");
            for (int a = 0; a < 3; ++a)
                if (!parseFloat(tok[1 + a], p[a])) r.fail("bad vertex coordinate '" + std::string(tok[1 + a]) + "'");
            if (n == 7)
                for (int a = 0; a < 3; ++a)
                    if (!parseFloat(tok[4 + a], c[a])) r.fail("bad vertex colour");
            colours = colours && n == 7;
            m.positions.push_back(p);
            m.colours.push_back(glm::u8vec3(glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f));
        } else if (tok[0] == "f") {
            if (n < 4) r.fail("a face needs at least 3 vertices");
            face.clear();
            for (std::size_t k = 1; k < n; ++k) {
                const std::string_view idx = tok[k].substr(0, tok[k].find('/'));
                long long i;
                if (!parseInt(idx, i) || i == 0) r.fail("bad face index '" + std::string(tok[k]) + "'");
                const long long count = (long long)m.positions.size();
                const long long zeroBased = i > 0 ? i - 1 : count + i;  // negative: relative to the end
                if (zeroBased < 0 || zeroBased >= count) r.fail("face index " + std::to_string(i) + " out of range");
                face.push_back(uint32_t(zeroBased));
            }
            addPolygon(m, face.data(), face.size());
        }
        // vt, vn, g, o, s, usemtl, mtllib, l, p: not geometry we need
    }
    if (!colours) m.colours.clear();
    return m;
}

/// Welds exactly equal positions (STL stores three per facet).
struct Welder {
    MeshBuffers& m;
    std::unordered_map<uint64_t, std::vector<uint32_t>> buckets;
    uint32_t add(glm::vec3 p) {
        p += glm::vec3(0.0f);  // -0 becomes +0, so equal positions hash equally
        uint32_t bits[3];
        std::memcpy(bits, &p, 12);
        const uint64_t key = (uint64_t(bits[0]) * 0x9e3779b97f4a7c15ull) ^ (uint64_t(bits[1]) << 21) ^ bits[2];
        auto& bucket = buckets[key];
        for (uint32_t i : bucket)
            if (m.positions[i] == p) return i;
        m.positions.push_back(p);
        bucket.push_back(uint32_t(m.positions.size() - 1));
        return bucket.back();
    }
};

MeshBuffers readStl(std::string_view bytes, const std::string& name) {
    MeshBuffers m;
    Welder weld{m, {}};
    if (bytes.size() >= 84) {
        uint32_t count;
        std::memcpy(&count, bytes.data() + 80, 4);
        if (84 + uint64_t(count) * 50 == bytes.size()) {  // binary: the size says so exactly
            for (uint32_t t = 0; t < count; ++t) {
                const char* rec = bytes.data() + 84 + std::size_t(t) * 50;
                uint32_t tri[3];
                for (int k = 0; k < 3; ++k) {
                    glm::vec3 p;
                    std::memcpy(&p, rec + 12 + 12 * k, 12);
                    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                        throw FileError(name, "facet " + std::to_string(t) + " has a non-finite vertex");
                    tri[k] = weld.add(p);
                }
                addPolygon(m, tri, 3);
            }
            return m;
        }
    }
    if (bytes.substr(0, 5) != "solid")
        throw FileError(name, bytes.size() >= 84 ? "binary STL size does not match its facet count (truncated?)"
                                                 : "not an STL file (too short, and no 'solid' header)");
    TextReader r(bytes, name);
    std::string_view line;
    std::vector<std::string_view> tok;
    uint32_t tri[3];
    int corner = 0;
    while (r.nextLine(line)) {
        const std::size_t n = split(line, tok);
        if (n == 0) continue;
        if (tok[0] == "vertex") {
            glm::vec3 p;
            if (n != 4) r.fail("a vertex needs 3 coordinates");
            for (int a = 0; a < 3; ++a)
                if (!parseFloat(tok[1 + a], p[a])) r.fail("bad vertex coordinate '" + std::string(tok[1 + a]) + "'");
            if (corner == 3) r.fail("a facet has more than 3 vertices");
            tri[corner++] = weld.add(p);
        } else if (tok[0] == "endloop") {
            if (corner != 3) r.fail("a facet needs 3 vertices");
            addPolygon(m, tri, 3);
            corner = 0;
        }
    }
    if (corner != 0) throw FileError(name, "truncated: the last facet is incomplete");
    return m;
}

// ---- PLY ----

struct PlyProperty {
    std::string name;
    int type = 0;       ///< bytes of the scalar (or of the list items); negative for float types
    bool isSigned = false;
    bool list = false;
    int countType = 0;  ///< bytes of the list count
};
struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> props;
};

/// Size in bytes of a PLY scalar type; floats are returned negative. 0 if unknown.
int plyType(std::string_view t, bool& isSigned) {
    isSigned = t == "char" || t == "short" || t == "int" || t == "int8" || t == "int16" || t == "int32";
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32") return 4;
    if (t == "float" || t == "float32") return -4;
    if (t == "double" || t == "float64") return -8;
    return 0;
}

/// Reads PLY values in ASCII or binary of either byte order, bounds-checked.
class PlyValues {
public:
    PlyValues(std::string_view body, int format, const std::string& name) : mBody(body), mFormat(format), mName(name) {}
    double read(int type, bool isSigned) {
        if (mFormat == 0) return readText();
        const std::size_t n = std::size_t(std::abs(type));
        if (n > mBody.size() - mPos) throw FileError(mName, "truncated: the data ends before the last element");
        unsigned char b[8];
        std::memcpy(b, mBody.data() + mPos, n);
        mPos += n;
        if (mFormat == 2) std::reverse(b, b + n);  // big-endian file on a little-endian host
        switch (type) {
            case 1: return isSigned ? double(int8_t(b[0])) : double(b[0]);
            case 2: { uint16_t v; std::memcpy(&v, b, 2); return isSigned ? double(int16_t(v)) : double(v); }
            case 4: { uint32_t v; std::memcpy(&v, b, 4); return isSigned ? double(int32_t(v)) : double(v); }
            case -4: { float v; std::memcpy(&v, b, 4); return double(v); }
            default: { double v; std::memcpy(&v, b, 8); return v; }
        }
    }
    std::size_t bytesLeft() const { return mBody.size() - mPos; }

private:
    double readText() {
        while (mPos < mBody.size() && std::isspace(static_cast<unsigned char>(mBody[mPos]))) ++mPos;
        const std::size_t start = mPos;
        while (mPos < mBody.size() && !std::isspace(static_cast<unsigned char>(mBody[mPos]))) ++mPos;
        if (start == mPos) throw FileError(mName, "truncated: the data ends before the last element");
        double v;
        const auto [end, ec] = std::from_chars(mBody.data() + start, mBody.data() + mPos, v);
        if (ec != std::errc() || end != mBody.data() + mPos)
            throw FileError(mName, "bad number '" + std::string(mBody.substr(start, mPos - start)) + "'");
        return v;
    }
    std::string_view mBody;
    std::size_t mPos = 0;
    int mFormat;  ///< 0 ascii, 1 little-endian, 2 big-endian
    const std::string& mName;
};

uint8_t colourByte(double v) { return std::isfinite(v) ? uint8_t(std::clamp(v, 0.0, 255.0)) : 0; }

MeshBuffers readPly(std::string_view bytes, const std::string& name) {
    if (bytes.substr(0, 3) != "ply") throw FileError(name, "not a PLY file (no 'ply' magic)");
    TextReader r(bytes, name);
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
            format = tok[1] == "ascii" ? 0 : tok[1] == "binary_little_endian" ? 1 : tok[1] == "binary_big_endian" ? 2 : -1;
            if (format < 0) r.fail("unknown PLY format '" + std::string(tok[1]) + "'");
        } else if (tok[0] == "element") {
            PlyElement e;
            if (n != 3 || !parseInt(tok[2], e.count)) r.fail("an element needs a name and a count");
            e.name = std::string(tok[1]);
            for (const PlyElement& other : elements)
                if (other.name == e.name) r.fail("element '" + e.name + "' appears twice");
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
                if (p.type == 0) r.fail("unknown property type '" + std::string(tok[1]) + "'");
            } else {
                r.fail("malformed property line");
            }
            elements.back().props.push_back(p);
        } else if (tok[0] == "end_header") {
            ended = true;
        } else {
            r.fail("unexpected header line '" + std::string(tok[0]) + "'");
        }
    }
    if (!ended) throw FileError(name, "truncated: no end_header");
    if (format < 0) throw FileError(name, "the header has no format line");

    PlyValues values(bytes.substr(r.offset()), format, name);
    MeshBuffers m;
    bool haveColours = false;
    std::vector<uint32_t> face;
    for (const PlyElement& e : elements) {
        // Every value takes at least one byte (binary) or two characters (ASCII), so an entry
        // takes at least as many bytes as it has properties: bound the count before reading.
        if (e.props.empty() && e.count > 0) throw FileError(name, "element '" + e.name + "' has entries but no properties");
        if (e.count > values.bytesLeft() / std::max<std::size_t>(1, e.props.size()))
            throw FileError(name, "element '" + e.name + "' claims more entries than the file holds");
        const bool isVertex = e.name == "vertex", isFace = e.name == "face";
        if (isVertex) {
            m.positions.reserve(std::size_t(e.count));
            haveColours = std::any_of(e.props.begin(), e.props.end(), [](const PlyProperty& p) { return p.name == "red"; });
        }
        for (uint64_t i = 0; i < e.count; ++i) {
            glm::vec3 p(0.0f);
            glm::u8vec3 c(0);
            for (const PlyProperty& prop : e.props) {
                if (prop.list) {
                    const double count = values.read(prop.countType, false);
                    if (!isIndex(count, 1e6)) throw FileError(name, "a list of " + std::to_string(count) + " items");
                    face.clear();
                    for (int k = 0; k < int(count); ++k) {
                        const double v = values.read(prop.type, prop.isSigned);
                        if (isFace && (prop.name == "vertex_indices" || prop.name == "vertex_index")) {
                            if (!isIndex(v, double(m.positions.size())))
                                throw FileError(name, "face " + std::to_string(i) + " has vertex index " + std::to_string(v) + " out of range");
                            face.push_back(uint32_t(v));
                        }
                    }
                    if (!face.empty()) {
                        if (face.size() < 3) throw FileError(name, "face " + std::to_string(i) + " has fewer than 3 vertices");
                        addPolygon(m, face.data(), face.size());
                    }
                    continue;
                }
                const double v = values.read(prop.type, prop.isSigned);
                if (!isVertex) continue;
                if (prop.name == "x") p.x = float(v);
                else if (prop.name == "y") p.y = float(v);
                else if (prop.name == "z") p.z = float(v);
                else if (prop.name == "red") c.r = colourByte(v);
                else if (prop.name == "green") c.g = colourByte(v);
                else if (prop.name == "blue") c.b = colourByte(v);
            }
            if (isVertex) {
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    throw FileError(name, "vertex " + std::to_string(i) + " is not finite");
                m.positions.push_back(p);
                if (haveColours) m.colours.push_back(c);
            }
        }
    }
    return m;
}

MeshBuffers readOff(std::string_view text, const std::string& name) {
    TextReader r(text, name);
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
    if (tok[0] != "OFF" && tok[0] != "COFF" && tok[0] != "NOFF") throw FileError(name, "not an OFF file (no OFF header)");
    // The counts may follow the keyword on the same line.
    std::size_t at = 1;
    if (n == 1) {
        n = next();
        at = 0;
    }
    uint64_t nv, nf;
    if (n < at + 2 || !parseInt(tok[at], nv) || !parseInt(tok[at + 1], nf)) r.fail("expected vertex and face counts");
    if (nv > r.bytesLeft() || nf > r.bytesLeft()) r.fail("counts exceed the size of the file");
    MeshBuffers m;
    m.positions.reserve(std::size_t(nv));
    for (uint64_t i = 0; i < nv; ++i) {
        if (next() < 3) r.fail("a vertex needs 3 coordinates");
        glm::vec3 p;
        for (int a = 0; a < 3; ++a)
            if (!parseFloat(tok[a], p[a])) r.fail("bad vertex coordinate '" + std::string(tok[a]) + "'");
        m.positions.push_back(p);
    }
    std::vector<uint32_t> face;
    for (uint64_t f = 0; f < nf; ++f) {
        const std::size_t k = next();
        std::size_t count;
        if (!parseInt(tok[0], count) || count < 3 || count + 1 > k) r.fail("a face needs a count of at least 3 and that many indices");
        face.clear();
        for (std::size_t j = 0; j < count; ++j) {
            uint32_t i;
            if (!parseInt(tok[1 + j], i) || i >= m.positions.size()) r.fail("face index '" + std::string(tok[1 + j]) + "' out of range");
            face.push_back(i);
        }
        addPolygon(m, face.data(), face.size());
    }
    return m;
}

}  // namespace

MeshBuffers decodeMesh(std::string_view bytes, MeshFormat format, const std::string& name) {
    if (bytes.empty()) throw FileError(name, "the file is empty");
    MeshBuffers m;
    switch (format) {
        case MeshFormat::Obj: m = readObj(bytes, name); break;
        case MeshFormat::Stl: m = readStl(bytes, name); break;
        case MeshFormat::Ply: m = readPly(bytes, name); break;
        case MeshFormat::Off: m = readOff(bytes, name); break;
        case MeshFormat::Glb: throw FileError(name, "reading .glb is not supported (use .obj, .stl, .ply or .off)");
    }
    if (m.triangleCount() == 0) throw FileError(name, "the file holds no triangles");
    return m;
}

MeshBuffers importMesh(const std::string& path) {
    const MeshFormat format = meshFormatOf(path);
    return decodeMesh(util::readWholeFile(path), format, path);
}

}  // namespace kizamu::mesh
