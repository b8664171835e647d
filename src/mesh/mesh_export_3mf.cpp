// SPDX-License-Identifier: Apache-2.0
/// @file mesh_export_3mf.cpp
/// @brief 3MF export through lib3mf 1.x's C interface (Debian's lib3mf-dev).
///
/// 3MF (3D Manufacturing Format, core specification 1.x) is what slicers read with its unit:
/// the model's `unit` attribute says what a coordinate means, so a print comes out at its size
/// whatever the slicer assumes for unitless files. Geometry only: one mesh object, one build
/// item, no colours or materials. lib3mf keeps its own copy of the mesh and builds the zip in
/// memory; the caller writes it atomically. Cold path; any thread (one lib3mf model per call).
#include "mesh/mesh_export_3mf.h"

#include "util/file_error.h"

#include <Model/COM/NMR_DLLInterfaces.h>

#include <cstring>
#include <memory>

namespace kizamu::mesh::detail {

namespace {

/// Releases a lib3mf instance (model, writer, mesh object, build item) at the end of its scope.
struct Release {
    void operator()(NMR::PLib3MFBase* p) const { NMR::lib3mf_release(p); }
};
using Handle = std::unique_ptr<NMR::PLib3MFBase, Release>;

/// Where lib3mf's writer puts the package: a byte buffer it may seek back into (the zip's
/// local headers are rewritten after their entries). The callbacks have the exact types of
/// lib3mf's ExportStream_WriteCallbackType and ExportStream_SeekCallbackType and return 0 for
/// success.
struct Sink {
    std::vector<std::byte>& bytes;
    std::size_t at;

    static unsigned write(unsigned char* data, unsigned n, void* user) {
        Sink& s = *static_cast<Sink*>(user);
        if (s.bytes.size() < s.at + n) s.bytes.resize(s.at + n);
        std::memcpy(s.bytes.data() + s.at, data, n);
        s.at += n;
        return 0;
    }
    static unsigned seek(unsigned long long position, void* user) {
        Sink& s = *static_cast<Sink*>(user);
        if (position > s.bytes.size()) return 1;
        s.at = std::size_t(position);
        return 0;
    }
};

DWORD modelUnit(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::Millimetre:
            return NMR::MODELUNIT_MILLIMETER;
        case LengthUnit::Centimetre:
            return NMR::MODELUNIT_CENTIMETER;
        case LengthUnit::Metre:
            return NMR::MODELUNIT_METER;
    }
    return NMR::MODELUNIT_MILLIMETER;
}

}  // namespace

void writeThreeMf(const MeshBuffers& m, std::span<const glm::vec3> pos, LengthUnit unit,
                  const std::string& path, std::vector<std::byte>& out) {
    NMR::PLib3MFModel* rawModel = nullptr;
    if (NMR::lib3mf_createmodel(&rawModel) != LIB3MF_OK || !rawModel)
        throw FileError(path, "lib3mf could not create a model");
    const Handle model(rawModel);
    // Every later failure is reported with the model's last error.
    auto check = [&](LIB3MFRESULT r, const char* step) {
        if (r == LIB3MF_OK) return;
        DWORD code = 0;
        LPCSTR message = nullptr;
        NMR::lib3mf_getlasterror(model.get(), &code, &message);
        throw FileError(path,
                        std::string("lib3mf failed to ") + step + ": " +
                            (message && *message ? message : "error " + std::to_string(code)));
    };
    check(NMR::lib3mf_model_setunit(model.get(), modelUnit(unit)), "set the unit");

    static_assert(sizeof(NMR::MODELMESHVERTEX) == sizeof(glm::vec3) &&
                  sizeof(NMR::MODELMESHTRIANGLE) == 12);
    std::vector<NMR::MODELMESHVERTEX> vertices(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i)
        std::memcpy(vertices[i].m_fPosition, &pos[i], sizeof(glm::vec3));
    std::vector<NMR::MODELMESHTRIANGLE> triangles(m.triangleCount());
    std::memcpy(triangles.data(), m.indices.data(), m.indices.size() * sizeof(uint32_t));

    NMR::PLib3MFModelMeshObject* rawMesh = nullptr;
    check(NMR::lib3mf_model_addmeshobject(model.get(), &rawMesh), "add the mesh object");
    const Handle meshObject(rawMesh);
    check(NMR::lib3mf_object_setnameutf8(meshObject.get(), "Kizamu clay"), "name the mesh object");
    check(NMR::lib3mf_meshobject_setgeometry(meshObject.get(), vertices.data(),
                                             DWORD(vertices.size()), triangles.data(),
                                             DWORD(triangles.size())),
          "set the geometry");
    vertices = {};
    triangles = {};
    NMR::PLib3MFModelBuildItem* rawItem = nullptr;
    check(NMR::lib3mf_model_addbuilditem(model.get(), meshObject.get(), nullptr, &rawItem),
          "add the build item");
    const Handle buildItem(rawItem);

    NMR::PLib3MFModelWriter* rawWriter = nullptr;
    check(NMR::lib3mf_model_querywriter(model.get(), "3mf", &rawWriter), "create a 3MF writer");
    const Handle writer(rawWriter);
    // Through callbacks into `out`: asking lib3mf for the size first (writetobuffer) would
    // write the package twice.
    Sink sink{out, 0};
    out.clear();
    check(NMR::lib3mf_writer_writetocallback(writer.get(), reinterpret_cast<void*>(&Sink::write),
                                             reinterpret_cast<void*>(&Sink::seek), &sink),
          "write the package");
}

glm::vec3 threeMfWritten(const glm::vec3& p) {
    glm::vec3 out;
    for (int k = 0; k < 3; ++k) {
        const auto micro = static_cast<long long>(p[k] * 1e6f);  // lib3mf's float product, truncated
        out[k] = static_cast<float>(static_cast<double>(micro) / 1e6);
    }
    return out;
}

}  // namespace kizamu::mesh::detail
