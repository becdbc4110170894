// The assimp peer of pnb_load_probe: what a viewer built on assimp does to show a file.
// ReadFile with Triangulate | JoinIdenticalVertices | GenSmoothNormals (an indexed mesh with
// normals: the flags of the reference figure of issue 13), every texture any material names
// decoded by stb_image to RGBA8 (embedded ones from memory, others from their files, each once),
// then one GL buffer + vertex array per mesh (positions, normals, UV0 straight from assimp's
// arrays; the indices gathered from its faces), every texture with a full mip chain, and one
// program per distinct material feature set (peer_gl.h).
#include <assimp/DefaultIOSystem.h>
#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <stb_image.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>

#include "peer_gl.h"
#include "probe.h"

namespace pnb::bench {

namespace {

namespace fs = std::filesystem;

// (Not "absolutePath": DefaultIOSystem has a static member of that name, which returns the
// directory, and would win the lookup inside the class below.)
std::string normalisedPath(const fs::path& p) {
    return fs::absolute(p).lexically_normal().string();
}

// The default file system, noting every file assimp opens (the MTL, a .gltf's .bin, ...).
class RecordingIoSystem : public Assimp::DefaultIOSystem {
public:
    explicit RecordingIoSystem(std::set<std::string>& files) : files_(files) {}
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        Assimp::IOStream* s = DefaultIOSystem::Open(file, mode);
        std::error_code ec; // only regular files hold data the load read
        if (s != nullptr && fs::is_regular_file(file, ec)) files_.insert(normalisedPath(file));
        return s;
    }

private:
    std::set<std::string>& files_;
};

struct StbPixels {
    struct Free {
        void operator()(stbi_uc* p) const { stbi_image_free(p); }
    };
    std::unique_ptr<stbi_uc, Free> pixels;
    int width = 0, height = 0;
};

// The texture a material names, decoded. `key` is the material's path string.
StbPixels decodeTexture(const aiScene& scene, const std::string& key, const fs::path& dir,
                        std::set<std::string>& files) {
    StbPixels out;
    int channels = 0;
    if (const aiTexture* t = scene.GetEmbeddedTexture(key.c_str())) {
        if (t->mHeight == 0) {
            out.pixels.reset(stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(t->pcData),
                                                   int(t->mWidth), &out.width, &out.height,
                                                   &channels, 4));
        } else { // raw BGRA texels: reorder, as stb_image would have delivered them
            const size_t n = size_t(t->mWidth) * t->mHeight;
            out.pixels.reset(static_cast<stbi_uc*>(std::malloc(n * 4)));
            for (size_t i = 0; i < n; ++i) {
                const aiTexel& x = t->pcData[i];
                stbi_uc* o = out.pixels.get() + i * 4;
                o[0] = x.r, o[1] = x.g, o[2] = x.b, o[3] = x.a;
            }
            out.width = int(t->mWidth);
            out.height = int(t->mHeight);
        }
        if (!out.pixels)
            throw LoadFailure("stb_image cannot decode embedded texture " + key + ": " +
                              stbi_failure_reason());
        return out;
    }
    // Windows separators are common in MTL files (".\\wall.jpg"); a viewer accepts them.
    std::string relative = key;
    std::replace(relative.begin(), relative.end(), '\\', '/');
    const std::string file = normalisedPath(dir / relative);
    out.pixels.reset(stbi_load(file.c_str(), &out.width, &out.height, &channels, 4));
    if (!out.pixels)
        throw LoadFailure("stb_image cannot decode " + file + ": " + stbi_failure_reason());
    files.insert(file);
    return out;
}

std::string texturePath(const aiMaterial& m, aiTextureType type) {
    aiString path;
    if (m.GetTextureCount(type) == 0 || m.GetTexture(type, 0, &path) != AI_SUCCESS) return {};
    return path.C_Str();
}

std::string baseColorPath(const aiMaterial& m) {
    std::string p = texturePath(m, aiTextureType_BASE_COLOR);
    return p.empty() ? texturePath(m, aiTextureType_DIFFUSE) : p;
}

std::string normalMapPath(const aiMaterial& m) {
    std::string p = texturePath(m, aiTextureType_NORMALS);
    return p.empty() ? texturePath(m, aiTextureType_HEIGHT) : p; // OBJ's bump
}

} // namespace

ProbeResult loadAssimp(const std::string& path) {
    ProbeResult r;
    Assimp::Importer importer;
    importer.SetIOHandler(new RecordingIoSystem(r.files)); // the importer owns it
    const auto start = Clock::now();
    auto phase = start;
    const aiScene* scene = importer.ReadFile(
        path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals);
    if (scene == nullptr)
        throw LoadFailure("assimp cannot read " + path + ": " + importer.GetErrorString());
    r.files.insert(normalisedPath(path));
    const double importMs = msSince(phase);

    // Decode: every texture any material names, once each.
    phase = Clock::now();
    const fs::path dir = fs::path(path).parent_path();
    std::map<std::string, StbPixels> decoded;
    for (unsigned m = 0; m < scene->mNumMaterials; ++m)
        for (int type = aiTextureType_NONE + 1; type <= AI_TEXTURE_TYPE_MAX; ++type) {
            const auto tt = aiTextureType(type);
            for (unsigned i = 0; i < scene->mMaterials[m]->GetTextureCount(tt); ++i) {
                aiString p;
                if (scene->mMaterials[m]->GetTexture(tt, i, &p) != AI_SUCCESS) continue;
                if (!decoded.count(p.C_Str()))
                    decoded.emplace(p.C_Str(), decodeTexture(*scene, p.C_Str(), dir, r.files));
            }
        }
    const double decodeMs = msSince(phase);

    phase = Clock::now();
    auto gl = std::make_unique<PeerGl>();
    for (auto& [key, px] : decoded) {
        gl->textureRgba8(px.pixels.get(), px.width, px.height);
        px.pixels.reset();
    }
    std::vector<uint32_t> indices;
    std::vector<uint32_t> meshFeatures(scene->mNumMeshes);
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const aiMesh& mesh = *scene->mMeshes[i];
        indices.clear();
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            indices.insert(indices.end(), face.mIndices, face.mIndices + face.mNumIndices);
            r.triangles += face.mNumIndices == 3 ? 1 : 0;
        }
        const uint64_t vec3Bytes = uint64_t(mesh.mNumVertices) * sizeof(aiVector3D);
        const bool normals = mesh.mNormals != nullptr, uv = mesh.mTextureCoords[0] != nullptr;
        const uint64_t normalAt = vec3Bytes, uvAt = normalAt + (normals ? vec3Bytes : 0);
        const uint64_t indexAt = uvAt + (uv ? vec3Bytes : 0);
        const uint64_t total = indexAt + indices.size() * sizeof(uint32_t);
        const GLuint b = gl->buffer(total, nullptr);
        glNamedBufferSubData(b, 0, GLsizeiptr(vec3Bytes), mesh.mVertices);
        if (normals)
            glNamedBufferSubData(b, GLintptr(normalAt), GLsizeiptr(vec3Bytes), mesh.mNormals);
        if (uv)
            glNamedBufferSubData(b, GLintptr(uvAt), GLsizeiptr(vec3Bytes), mesh.mTextureCoords[0]);
        glNamedBufferSubData(b, GLintptr(indexAt), GLsizeiptr(indices.size() * sizeof(uint32_t)),
                             indices.data());
        const GLuint va = gl->vertexArray();
        auto attribute = [&](GLuint loc, GLint size, uint64_t offset) {
            glEnableVertexArrayAttrib(va, loc);
            glVertexArrayAttribFormat(va, loc, size, GL_FLOAT, GL_FALSE, 0);
            glVertexArrayAttribBinding(va, loc, loc);
            glVertexArrayVertexBuffer(va, loc, b, GLintptr(offset), sizeof(aiVector3D));
        };
        attribute(0, 3, 0);
        if (normals) attribute(1, 3, normalAt);
        if (uv) attribute(2, 2, uvAt); // assimp keeps UVs as vec3: read two of the three
        glVertexArrayElementBuffer(va, b);

        const aiMaterial& mat = *scene->mMaterials[mesh.mMaterialIndex];
        uint32_t f = (normals ? uint32_t(kHasNormals) : 0u) | (uv ? uint32_t(kHasUv0) : 0u);
        if (uv && !baseColorPath(mat).empty()) f |= kBaseColorMap;
        if (uv && !normalMapPath(mat).empty()) f |= kNormalMap;
        aiString alphaMode;
        if (mat.Get(AI_MATKEY_GLTF_ALPHAMODE, alphaMode) == AI_SUCCESS &&
            std::string(alphaMode.C_Str()) == "MASK")
            f |= kAlphaMask;
        meshFeatures[i] = f;
    }
    glFinish();
    const double uploadMs = msSince(phase);

    const auto [mipsMs, compileMs] = gl->mipsAndPrograms(meshFeatures);
    r.gpuReadyMs = msSince(start);
    r.phases = {{"import", importMs},
                {"decode", decodeMs},
                {"upload", uploadMs},
                {"mips", mipsMs},
                {"compile", compileMs}};
    gl->countInto(r);

    const auto down = Clock::now();
    importer.FreeScene();
    gl.reset();
    glFinish();
    r.teardownMs = msSince(down);
    return r;
}

} // namespace pnb::bench
