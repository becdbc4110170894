// bench/load/peer_gl.h — what the peer loaders (assimp, tinygltf) of pnb_load_probe share to get
// a scene GPU-ready the way a straightforward viewer does: RGBA8 textures with immutable storage
// and a full mip chain from glGenerateTextureMipmap, and one simple lit program per distinct
// material feature set, compiled and linked (link status queried, so the work is done).
//
// A texture's mip chain comes from glGenerateTextureMipmap (what a viewer without an offline
// step does); the probe times it as its own phase ("mips").
//
// The programs: vertex position / normal / UV0 in, one directional light + ambient out. Feature
// bits pick #defines: HAS_NORMALS (else a face normal from derivatives), HAS_UV0, BASE_COLOR_MAP,
// NORMAL_MAP (cotangent frame from derivatives: no tangent stream needed), ALPHA_MASK. That is
// far less shading than the player's programs; it is what the peers are given so that "programs
// linked" is part of their GPU-ready too.
//
// Does NOT do: draw anything, sRGB formats, 16-bit or HDR textures (decoded to RGBA8 like
// tinygltf's default loader).
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <epoxy/gl.h>

#include "probe.h"

namespace pnb::bench {

// A failure a peer reports instead of a figure (the runner lists the model as skipped).
struct LoadFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum FeatureBits : uint32_t {
    kHasNormals = 1u << 0,
    kHasUv0 = 1u << 1,
    kBaseColorMap = 1u << 2,
    kNormalMap = 1u << 3,
    kAlphaMask = 1u << 4,
};

// GL objects a peer created, freed together (the probe times teardown separately).
class PeerGl {
public:
    PeerGl() = default;
    PeerGl(const PeerGl&) = delete;
    PeerGl& operator=(const PeerGl&) = delete;
    ~PeerGl();

    // A new buffer with immutable storage of `bytes`, filled from `data` (null: filled later with
    // glNamedBufferSubData, which the storage allows).
    GLuint buffer(uint64_t bytes, const void* data);
    GLuint vertexArray();
    // RGBA8 pixels of w x h: immutable storage with every mip level, level 0 uploaded. The rest
    // of the chain is left to generateMipmaps().
    GLuint textureRgba8(const uint8_t* pixels, int width, int height);
    // glGenerateTextureMipmap on every texture made so far, then glFinish. Apart from the upload
    // because on llvmpipe the first call also JIT-compiles the driver's blit shaders.
    void generateMipmaps();
    // The program for `features`, compiled and linked on first use. Throws LoadFailure if the
    // driver refuses it (with its log).
    GLuint program(uint32_t features);
    // The last two phases of every peer load, each through glFinish: the mip chains, then one
    // program per distinct feature set in `features`; returns {mips ms, compile ms}.
    std::pair<double, double> mipsAndPrograms(const std::vector<uint32_t>& features);

    uint64_t bufferBytes = 0, textureBytes = 0;
    uint32_t textures = 0, mipLevels = 0;
    size_t programCount() const { return programs_.size(); }
    // What was made, into the probe's result.
    void countInto(ProbeResult& r) const {
        r.textures = textures;
        r.mipLevels = mipLevels;
        r.programs = programCount();
        r.bufferBytes = bufferBytes;
        r.textureBytes = textureBytes;
    }

private:
    std::vector<GLuint> buffers_, vertexArrays_, textures_;
    std::map<uint32_t, GLuint> programs_;
};

} // namespace pnb::bench
