// SPDX-License-Identifier: Apache-2.0
/// @file assimp_read.cpp
/// @brief assimp's scene, flattened into one triangle mesh (see assimp_read.h).
#include "import/assimp_read.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <unordered_map>
#include <utility>

namespace kizamu::import {

namespace {

using mesh::MeshBuffers;

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

/// The file system, with one more name for one file: FILE.EXT for FILE, so that assimp picks
/// its reader by EXT and finds the files FILE refers to in FILE's folder.
class AliasIOSystem : public Assimp::DefaultIOSystem {
public:
    AliasIOSystem(std::string alias, std::string real)
        : mAlias(std::move(alias)), mReal(std::move(real)) {}
    bool Exists(const char* file) const override {
        return Assimp::DefaultIOSystem::Exists(mAlias == file ? mReal.c_str() : file);
    }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        return Assimp::DefaultIOSystem::Open(mAlias == file ? mReal.c_str() : file, mode);
    }

private:
    std::string mAlias, mReal;
};

/// Joins exactly equal positions (-0 and +0 alike) across the scene's meshes.
struct Welder {
    struct Key {
        uint32_t bits[3];
        bool operator==(const Key& o) const { return std::memcmp(bits, o.bits, 12) == 0; }
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            return std::size_t((uint64_t(k.bits[0]) * 0x9e3779b97f4a7c15ull) ^
                               (uint64_t(k.bits[1]) << 21) ^ k.bits[2]);
        }
    };
    MeshBuffers& m;
    std::unordered_map<Key, uint32_t, Hash> index;
    uint32_t add(glm::vec3 p) {
        p += glm::vec3(0.0f);
        Key k;
        std::memcpy(k.bits, &p, 12);
        const auto [it, added] = index.try_emplace(k, uint32_t(m.positions.size()));
        if (added) m.positions.push_back(p);
        return it->second;
    }
};

/// The scene's triangles as one mesh; an error message instead when there are none or a
/// vertex is not finite.
std::string flatten(const aiScene& scene, MeshBuffers& out) {
    Welder weld{out, {}};
    std::vector<uint32_t> remap;
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        const aiMesh* mesh = scene.mMeshes[i];
        if (mesh == nullptr || (mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
        remap.resize(mesh->mNumVertices);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                return "vertex " + std::to_string(v) + " of mesh " + std::to_string(i) +
                       " is not finite";
            remap[v] = weld.add(glm::vec3(p.x, p.y, p.z));
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (int k = 0; k < 3; ++k) {
                if (face.mIndices[k] >= mesh->mNumVertices)
                    return "face " + std::to_string(f) + " of mesh " + std::to_string(i) +
                           " has an index out of range";
                out.indices.push_back(remap[face.mIndices[k]]);
            }
        }
        if (out.positions.size() > 0xFFFFFFF0u) return "more than 2^32 vertices";
    }
    if (out.indices.empty()) return "the file holds no triangles";
    return "";
}

}  // namespace

std::string readWithAssimp(const std::string& path, const std::string& as, MeshBuffers& out,
                           std::vector<std::string>& warnings) {
    Assimp::Importer importer;
    importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                                aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                    aiComponent_COLORS | aiComponent_TEXCOORDS |
                                    aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                    aiComponent_TEXTURES | aiComponent_LIGHTS |
                                    aiComponent_CAMERAS | aiComponent_MATERIALS);
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_RemoveComponent | aiProcess_Triangulate |
                           aiProcess_SortByPType | aiProcess_PreTransformVertices |
                           aiProcess_JoinIdenticalVertices | aiProcess_GlobalScale |
                           aiProcess_ValidateDataStructure;
    std::string name = path;
    if (!as.empty()) {
        name = path + "." + as;
        importer.SetIOHandler(new AliasIOSystem(name, path));  // the importer owns it
    }
    const aiScene* scene = importer.ReadFile(name, flags);
    if (scene == nullptr) return std::string("assimp cannot read it: ") + importer.GetErrorString();
    float unitCm = 0.0f;  // FBX only: centimetres per unit
    if (scene->mMetaData != nullptr && scene->mMetaData->Get("UnitScaleFactor", unitCm) &&
        unitCm != 100.0f)
        warnings.push_back("the file's unit is " + number(unitCm) +
                           " cm (FBX UnitScaleFactor): coordinates scaled by " +
                           number(double(unitCm) / 100.0) + " to metres");
    return flatten(*scene, out);
}

}  // namespace kizamu::import
