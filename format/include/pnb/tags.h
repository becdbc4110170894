// pnb/tags.h — the one place where chunk tags are defined (docs/FORMAT.md §4).
//
// A tag is four ASCII characters, stored in file order (tag "MESH" is the bytes 'M','E','S','H').
// Retired tags are never reused: add new ones at the end and document them in FORMAT.md.
#pragma once

#include <cstdint>
#include <string>

namespace pnb {

struct Tag {
    char c[4];

    constexpr bool operator==(const Tag& o) const {
        return c[0] == o.c[0] && c[1] == o.c[1] && c[2] == o.c[2] && c[3] == o.c[3];
    }
    // Printable form; non-printable bytes appear as '?'.
    std::string str() const;
};

namespace detail {
template <size_t N> consteval Tag makeTag(const char (&s)[N]) {
    static_assert(N == 5, "a chunk tag is exactly four characters");
    return Tag{{s[0], s[1], s[2], s[3]}};
}
} // namespace detail

// Chunk kinds of format 1.x, in the order a streamable file stores them (FORMAT.md §4.1).
namespace tags {
inline constexpr Tag kStrings = detail::makeTag("STRS");        // string table
inline constexpr Tag kSceneInfo = detail::makeTag("INFO");      // scene info
inline constexpr Tag kRenderSettings = detail::makeTag("RSET"); // render settings
inline constexpr Tag kShader = detail::makeTag("SHDR");         // one shader stage source
inline constexpr Tag kProgram = detail::makeTag("PROG");        // stages + permutation defines
inline constexpr Tag kTexture = detail::makeTag("TEXR");        // texture descriptor
inline constexpr Tag kMaterial = detail::makeTag("MATL");       // one material
inline constexpr Tag kMesh = detail::makeTag("MESH");           // one mesh
inline constexpr Tag kMorphTargets = detail::makeTag("MRPH");   // one mesh's morph targets
inline constexpr Tag kLights = detail::makeTag("LGHT");         // all lights
inline constexpr Tag kCameras = detail::makeTag("CAMR");        // all cameras
inline constexpr Tag kNodes = detail::makeTag("NODE");          // node graph
inline constexpr Tag kSkin = detail::makeTag("SKIN");           // one skin (joints, bind matrices)
inline constexpr Tag kAnimation = detail::makeTag("ANIM");      // one animation clip
inline constexpr Tag kCameraPath = detail::makeTag("PATH");     // one camera path
inline constexpr Tag kEnvironment = detail::makeTag("ENVM");    // sky light and background
inline constexpr Tag kTextureMip = detail::makeTag("TMIP");     // one mip level of a texture
inline constexpr Tag kMeshDetail = detail::makeTag("MDET");     // a mesh's full detail (its MESH: a proxy)
inline constexpr Tag kToc = detail::makeTag("TOCX");            // table of contents (last chunk)
} // namespace tags

// Rank of a known tag in the streamable order of FORMAT.md §4.1 (STRS 0 ... TMIP 16); -1 for
// TOCX and tags this version does not know. Chunks of equal rank may repeat and interleave:
// MDET shares TMIP's rank (the progressive section, after everything the first frame needs).
constexpr int streamOrderRank(Tag t) {
    if (t == tags::kMeshDetail) return 16;
    constexpr Tag order[] = {tags::kStrings,  tags::kSceneInfo,    tags::kRenderSettings,
                             tags::kShader,   tags::kProgram,      tags::kTexture,
                             tags::kMaterial, tags::kMesh,         tags::kMorphTargets,
                             tags::kLights,   tags::kCameras,      tags::kNodes,
                             tags::kSkin,     tags::kAnimation,    tags::kCameraPath,
                             tags::kEnvironment, tags::kTextureMip};
    for (int i = 0; i < int(sizeof(order) / sizeof(order[0])); ++i)
        if (order[i] == t) return i;
    return -1;
}

} // namespace pnb
