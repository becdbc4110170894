// The tinygltf peer of pnb_load_probe: LoadBinaryFromFile (.glb) or LoadASCIIFromFile (.gltf)
// with tinygltf's own image decoding (stb_image, RGBA8: the decoder the assimp peer uses too),
// then each glTF buffer uploaded once as one GL buffer (the way glTF is meant to be uploaded:
// accessors become vertex-array offsets into it, no repacking), one vertex array per primitive,
// every image as a texture with a full mip chain, and one program per distinct material feature
// set (peer_gl.h). The decode time is measured inside tinygltf's image callback; "import" is the
// rest of the load call.
//
// This file holds the tinygltf implementation of the probe (the probe does not link
// pnb_converter, which holds another); stb_image's implementation comes from Debian's libstb.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include <filesystem>
#include <memory>

#include "peer_gl.h"
#include "probe.h"

namespace pnb::bench {

namespace {

std::string absolutePath(const std::string& p) {
    return std::filesystem::absolute(p).lexically_normal().string();
}

struct Recorder {
    std::set<std::string>* files = nullptr;
    double decodeMs = 0;
};

bool recordingRead(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* user) {
    const bool ok = tinygltf::ReadWholeFile(out, err, path, nullptr);
    if (ok) static_cast<Recorder*>(user)->files->insert(absolutePath(path));
    return ok;
}

bool timedDecode(tinygltf::Image* image, const int index, std::string* err, std::string* warn,
                 int width, int height, const unsigned char* bytes, int size, void* user) {
    const auto start = Clock::now();
    const bool ok =
        tinygltf::LoadImageData(image, index, err, warn, width, height, bytes, size, nullptr);
    static_cast<Recorder*>(user)->decodeMs += msSince(start);
    return ok;
}

GLint componentCount(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return 1;
    case TINYGLTF_TYPE_VEC2:
        return 2;
    case TINYGLTF_TYPE_VEC3:
        return 3;
    case TINYGLTF_TYPE_VEC4:
        return 4;
    default:
        return 0;
    }
}

const tinygltf::Accessor& accessorAt(const tinygltf::Model& m, int index, const char* what) {
    if (index < 0 || size_t(index) >= m.accessors.size())
        throw LoadFailure(std::string(what) + " accessor " + std::to_string(index) +
                          " does not exist");
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    // Sparse, Draco- or meshopt-compressed data has no plain buffer view to point GL at.
    if (a.sparse.isSparse || a.bufferView < 0 || size_t(a.bufferView) >= m.bufferViews.size())
        throw LoadFailure(std::string(what) + " accessor " + std::to_string(index) +
                          " is sparse or compressed (not supported by the tinygltf peer)");
    return a;
}

} // namespace

ProbeResult loadTinygltf(const std::string& path) {
    ProbeResult r;
    Recorder recorder{&r.files, 0};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &recordingRead,
                           &tinygltf::WriteWholeFile, &recorder});
    loader.SetImageLoader(&timedDecode, &recorder);
    auto model = std::make_unique<tinygltf::Model>();
    std::string err, warn;
    const auto start = Clock::now();
    const bool binary = std::filesystem::path(path).extension() == ".glb";
    const bool ok = binary ? loader.LoadBinaryFromFile(model.get(), &err, &warn, path)
                           : loader.LoadASCIIFromFile(model.get(), &err, &warn, path);
    if (!ok) throw LoadFailure("tinygltf cannot read " + path + ": " + err);
    r.files.insert(absolutePath(path));
    const double loadMs = msSince(start);

    auto phase = Clock::now();
    auto gl = std::make_unique<PeerGl>();
    for (const tinygltf::Image& im : model->images) {
        if (im.image.empty()) throw LoadFailure("image " + im.name + " was not decoded");
        if (im.bits != 8 || im.component != 4)
            throw LoadFailure("image " + im.name +
                              " is not 8-bit RGBA after decoding "
                              "(not supported by the peer upload)");
        gl->textureRgba8(im.image.data(), im.width, im.height);
    }
    std::vector<GLuint> buffers;
    for (const tinygltf::Buffer& b : model->buffers)
        buffers.push_back(gl->buffer(b.data.size(), b.data.data()));
    std::vector<uint32_t> features;
    for (const tinygltf::Mesh& mesh : model->meshes)
        for (const tinygltf::Primitive& prim : mesh.primitives) {
            const GLuint va = gl->vertexArray();
            uint32_t f = 0;
            auto attribute = [&](const char* name, GLuint loc, uint32_t bit) {
                auto it = prim.attributes.find(name);
                if (it == prim.attributes.end()) return;
                const tinygltf::Accessor& a = accessorAt(*model, it->second, name);
                const tinygltf::BufferView& v = model->bufferViews[size_t(a.bufferView)];
                const GLint n = componentCount(a.type);
                const int stride = a.ByteStride(v);
                if (n == 0 || stride <= 0 || size_t(v.buffer) >= buffers.size())
                    throw LoadFailure(std::string(name) + " accessor has no usable layout");
                glEnableVertexArrayAttrib(va, loc);
                glVertexArrayAttribFormat(va, loc, n, GLenum(a.componentType),
                                          a.normalized ? GL_TRUE : GL_FALSE, 0);
                glVertexArrayAttribBinding(va, loc, loc);
                glVertexArrayVertexBuffer(va, loc, buffers[size_t(v.buffer)],
                                          GLintptr(v.byteOffset + a.byteOffset), stride);
                f |= bit;
            };
            if (prim.attributes.find("POSITION") == prim.attributes.end())
                throw LoadFailure("a primitive of mesh " + mesh.name + " has no POSITION");
            attribute("POSITION", 0, 0);
            attribute("NORMAL", 1, kHasNormals);
            attribute("TEXCOORD_0", 2, kHasUv0);
            uint64_t count = 0;
            if (prim.indices >= 0) {
                const tinygltf::Accessor& a = accessorAt(*model, prim.indices, "index");
                const tinygltf::BufferView& v = model->bufferViews[size_t(a.bufferView)];
                glVertexArrayElementBuffer(va, buffers[size_t(v.buffer)]);
                count = a.count;
            } else {
                count = accessorAt(*model, prim.attributes.at("POSITION"), "POSITION").count;
            }
            if (prim.mode == TINYGLTF_MODE_TRIANGLES || prim.mode == -1) r.triangles += count / 3;
            if (prim.material >= 0 && size_t(prim.material) < model->materials.size()) {
                const tinygltf::Material& m = model->materials[size_t(prim.material)];
                if ((f & kHasUv0) && m.pbrMetallicRoughness.baseColorTexture.index >= 0)
                    f |= kBaseColorMap;
                if ((f & kHasUv0) && m.normalTexture.index >= 0) f |= kNormalMap;
                if (m.alphaMode == "MASK") f |= kAlphaMask;
            }
            features.push_back(f);
        }
    glFinish();
    const double uploadMs = msSince(phase);

    const auto [mipsMs, compileMs] = gl->mipsAndPrograms(features);
    r.gpuReadyMs = msSince(start);
    r.phases = {{"import", loadMs - recorder.decodeMs},
                {"decode", recorder.decodeMs},
                {"upload", uploadMs},
                {"mips", mipsMs},
                {"compile", compileMs}};
    gl->countInto(r);

    const auto down = Clock::now();
    model.reset();
    gl.reset();
    glFinish();
    r.teardownMs = msSince(down);
    return r;
}

} // namespace pnb::bench
