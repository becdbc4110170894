// gpu_layout_test.cpp — every GPU block the player fills from C++ (shaders/shared/*.h), as the GL
// driver lays it out in the real programs, against the C++ struct: each member's GL_OFFSET
// against offsetof, array strides against the element's sizeof, the block's GL_BUFFER_DATA_SIZE
// (or a struct array's stride) against sizeof. The headers' static_asserts check the C++ side
// against the std140/std430 rules; this checks that the shaders the driver compiles agree, so a
// hand-written GLSL copy that drifts from the shared list fails here.
//
// The programs: the converter's forward surface program with every lighting feature (surface.vert
// + forward.frag with SHADOWS, GI, IBL: frame, object, material, shadow, GI and IBL blocks, the
// light list's, the light clusters' and the local shadow tiles' headers, the light,
// local-shadow-tile and instance arrays), resolved through the converter's own #include resolution; and the player's embedded
// flat.vert (frame and object blocks), sdsm.comp (its state, the shadow block as std430 storage,
// the casters), shadow_debug.frag (SDSM's state), light_clusters.comp and debug_view.frag (the
// light clusters' and the light list's headers), through the build's include inlining.
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "gl/program_compile.h"
#include "pnb_converter/shader_permutations.h"
#include "render_fixture.h"
#include "shared/frame_block.h"
#include "shared/gi_block.h"
#include "shared/gpu_light.h"
#include "shared/ibl_block.h"
#include "shared/instance_data.h"
#include "shared/light_cluster_masks.h"
#include "shared/light_list.h"
#include "shared/local_shadow_tile.h"
#include "shared/material_block.h"
#include "shared/object_block.h"
#include "shared/sdsm_caster.h"
#include "shared/sdsm_state.h"
#include "shared/shadow_block.h"

namespace pnb::player::test {
namespace {

// One member of a shared list, as C++ placed it.
struct MemberRow {
    std::string cppName, glslName;
    size_t offset = 0;
    size_t elementSize = 0; // arrays: sizeof one element (the GLSL array stride)
    bool array = false;
};

struct StructRows {
    std::vector<MemberRow> members;
    size_t size = 0;
};

template <class T> constexpr size_t elementSize() { return sizeof(std::remove_all_extents_t<T>); }

#define PNB_ROW_FIELD(type, cppName, glslName)                                                     \
    MemberRow{#cppName, #glslName, offsetof(Checked, cppName), 0, false},
#define PNB_ROW_ARRAY(type, cppName, glslName, count)                                              \
    MemberRow{#cppName, #glslName, offsetof(Checked, cppName),                                     \
              elementSize<decltype(Checked::cppName)>(), true},
// The rows of `Struct` from its member list, in order.
#define PNB_ROWS(Struct, MEMBERS)                                                                  \
    [] {                                                                                           \
        using Checked = Struct;                                                                    \
        return StructRows{{MEMBERS(PNB_ROW_FIELD, PNB_ROW_ARRAY)}, sizeof(Checked)};               \
    }()

enum class Names { Glsl, Cpp };

GLint resourceInt(GLuint program, GLenum interface, GLuint index, GLenum property) {
    GLint value = -1;
    glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
    return value;
}

// Expects `rows`' members at their C++ offsets in `program`: resource names are `prefix` + the
// member's name (+ "[0]" for arrays); offsets are taken relative to the first member's (0 for a
// block, the element's start for a struct in an array). Returns the first member's index.
GLuint expectMembers(GLuint program, GLenum interface, const std::string& prefix,
                     const StructRows& rows, Names names) {
    GLuint first = GL_INVALID_INDEX;
    GLint base = 0;
    for (const MemberRow& row : rows.members) {
        std::string name = prefix + (names == Names::Glsl ? row.glslName : row.cppName) +
                           (row.array ? "[0]" : "");
        GLuint index = glGetProgramResourceIndex(program, interface, name.c_str());
        EXPECT_NE(index, GL_INVALID_INDEX) << name << " is not an active resource";
        if (index == GL_INVALID_INDEX) continue;
        GLint offset = resourceInt(program, interface, index, GL_OFFSET);
        if (first == GL_INVALID_INDEX) {
            first = index;
            base = offset;
        }
        EXPECT_EQ(size_t(offset - base), row.offset) << name << ": GL offset against C++ offsetof";
        if (row.array) {
            EXPECT_EQ(size_t(resourceInt(program, interface, index, GL_ARRAY_STRIDE)),
                      row.elementSize)
                << name << ": GL array stride against the C++ element's sizeof";
        }
    }
    return first;
}

// A block whose members are the struct's (uniform or storage block): offsets from 0 and the
// block's data size.
void expectBlock(GLuint program, GLenum blockInterface, GLenum memberInterface,
                 const std::string& blockName, const std::string& prefix, const StructRows& rows,
                 Names names = Names::Glsl) {
    SCOPED_TRACE(blockName);
    GLuint block = glGetProgramResourceIndex(program, blockInterface, blockName.c_str());
    ASSERT_NE(block, GL_INVALID_INDEX) << blockName << " is not an active block";
    GLuint first = expectMembers(program, memberInterface, prefix, rows, names);
    ASSERT_NE(first, GL_INVALID_INDEX);
    EXPECT_EQ(resourceInt(program, memberInterface, first, GL_OFFSET), 0);
    EXPECT_EQ(size_t(resourceInt(program, blockInterface, block, GL_BUFFER_DATA_SIZE)), rows.size)
        << blockName << ": GL_BUFFER_DATA_SIZE against the C++ sizeof";
}

// A struct as the element of a storage buffer's array `arrayName` (std430): offsets within the
// element, and the array's stride against sizeof.
void expectArrayElement(GLuint program, const std::string& arrayName, const StructRows& rows,
                        Names names = Names::Glsl) {
    SCOPED_TRACE(arrayName);
    GLuint first = expectMembers(program, GL_BUFFER_VARIABLE, arrayName + "[0].", rows, names);
    ASSERT_NE(first, GL_INVALID_INDEX);
    EXPECT_EQ(size_t(resourceInt(program, GL_BUFFER_VARIABLE, first, GL_TOP_LEVEL_ARRAY_STRIDE)),
              rows.size)
        << arrayName << ": GL array stride against the C++ sizeof";
}

// A storage block that starts with a header struct's members: at their C++ offsets, and then
// either the block's unsized array, whose first resource `arrayResource` C++ writes right after
// the header (at sizeof), or (no array: "") nothing, the block's data size being the sizeof.
void expectHeaderBlock(GLuint program, const std::string& blockName, const StructRows& rows,
                       const std::string& arrayResource) {
    SCOPED_TRACE(blockName);
    GLuint block = glGetProgramResourceIndex(program, GL_SHADER_STORAGE_BLOCK, blockName.c_str());
    ASSERT_NE(block, GL_INVALID_INDEX) << blockName << " is not an active block";
    GLuint first = expectMembers(program, GL_BUFFER_VARIABLE, "", rows, Names::Glsl);
    ASSERT_NE(first, GL_INVALID_INDEX);
    EXPECT_EQ(resourceInt(program, GL_BUFFER_VARIABLE, first, GL_OFFSET), 0);
    if (arrayResource.empty()) {
        EXPECT_EQ(size_t(resourceInt(program, GL_SHADER_STORAGE_BLOCK, block, GL_BUFFER_DATA_SIZE)),
                  rows.size)
            << blockName << ": GL_BUFFER_DATA_SIZE against the C++ sizeof";
        return;
    }
    GLuint array = glGetProgramResourceIndex(program, GL_BUFFER_VARIABLE, arrayResource.c_str());
    ASSERT_NE(array, GL_INVALID_INDEX) << arrayResource << " is not an active resource";
    EXPECT_EQ(size_t(resourceInt(program, GL_BUFFER_VARIABLE, array, GL_OFFSET)), rows.size)
        << arrayResource << ": GL offset against the C++ header's sizeof";
}

// The converter's program `vertex` + `fragment` as it packs them (its #include resolution over
// the embedded shaders/), compiled by the player with `defines`.
GlHandle converterProgram(std::string_view vertex, std::string_view fragment,
                          std::span<const std::string_view> defines) {
    auto v = converter::resolveShaderSource(vertex, converter::builtinShaderFiles());
    auto f = converter::resolveShaderSource(fragment, converter::builtinShaderFiles());
    EXPECT_TRUE(v.ok() && f.ok());
    if (!v.ok() || !f.ok()) return {};
    StageSource stages[] = {{GL_VERTEX_SHADER, v->text}, {GL_FRAGMENT_SHADER, f->text}};
    auto program = compileProgram("layout probe", stages, defines);
    EXPECT_TRUE(program.ok()) << program.error().message;
    return program.ok() ? std::move(*program) : GlHandle{};
}

TEST(GpuLayout, SurfaceProgramBlocksMatchTheCppStructs) {
    const std::string_view defines[] = {"SHADOWS", "GI", "IBL"};
    GlHandle program = converterProgram("surface.vert", "forward.frag", defines);
    ASSERT_TRUE(bool(program));
    const GLuint p = program.id();
    expectBlock(p, GL_UNIFORM_BLOCK, GL_UNIFORM, "FrameBlock", "",
                PNB_ROWS(FrameBlock, PNB_FRAME_BLOCK_MEMBERS));
    expectBlock(p, GL_UNIFORM_BLOCK, GL_UNIFORM, "ObjectBlock", "",
                PNB_ROWS(ObjectBlock, PNB_OBJECT_BLOCK_MEMBERS));
    expectBlock(p, GL_UNIFORM_BLOCK, GL_UNIFORM, "MaterialBlock", "",
                PNB_ROWS(MaterialBlock, PNB_MATERIAL_BLOCK_MEMBERS));
    expectBlock(p, GL_UNIFORM_BLOCK, GL_UNIFORM, "ShadowBlock", "",
                PNB_ROWS(ShadowBlock, PNB_SHADOW_BLOCK_MEMBERS));
    expectBlock(p, GL_UNIFORM_BLOCK, GL_UNIFORM, "GiBlock", "",
                PNB_ROWS(GiBlock, PNB_GI_BLOCK_MEMBERS));
    expectBlock(p, GL_UNIFORM_BLOCK, GL_UNIFORM, "IblBlock", "",
                PNB_ROWS(IblBlock, PNB_IBL_BLOCK_MEMBERS));
    expectArrayElement(p, "uLights", PNB_ROWS(GpuLight, PNB_GPU_LIGHT_MEMBERS));
    expectArrayElement(p, "uLocalShadowTiles",
                       PNB_ROWS(GpuShadowTile, PNB_LOCAL_SHADOW_TILE_MEMBERS));
    expectHeaderBlock(p, "LightBuffer", PNB_ROWS(LightListHeader, PNB_LIGHT_LIST_HEADER_MEMBERS),
                      "uLights[0].positionRange");
    expectHeaderBlock(p, "LightClusters",
                      PNB_ROWS(LightClustersHeader, PNB_LIGHT_CLUSTERS_HEADER_MEMBERS),
                      "uClusterMasks[0]");
    expectHeaderBlock(p, "LocalShadows",
                      PNB_ROWS(LocalShadowsHeader, PNB_LOCAL_SHADOWS_HEADER_MEMBERS),
                      "uLocalShadowTiles[0].matrix");
    expectArrayElement(p, "uInstances", PNB_ROWS(InstanceData, PNB_INSTANCE_DATA_MEMBERS));
}

TEST(GpuLayout, PlayerFlatProgramBlocksMatchTheCppStructs) {
    auto program = compileEmbeddedProgram("flat.vert", "flat.frag");
    ASSERT_TRUE(program.ok()) << program.error().message;
    expectBlock(program->id(), GL_UNIFORM_BLOCK, GL_UNIFORM, "FrameBlock", "",
                PNB_ROWS(FrameBlock, PNB_FRAME_BLOCK_MEMBERS));
    expectBlock(program->id(), GL_UNIFORM_BLOCK, GL_UNIFORM, "ObjectBlock", "",
                PNB_ROWS(ObjectBlock, PNB_OBJECT_BLOCK_MEMBERS));
}

TEST(GpuLayout, SdsmStorageMatchesTheCppStructs) {
    const std::string_view finalize[] = {"SDSM_FINALIZE"};
    auto fit = compileEmbeddedCompute("sdsm.comp", finalize);
    ASSERT_TRUE(fit.ok()) << fit.error().message;
    // The std430 copy of the shadow block that SDSM writes and lighting then binds as the
    // std140 ShadowBlock: the same bytes must mean the same members.
    expectBlock(fit->id(), GL_SHADER_STORAGE_BLOCK, GL_BUFFER_VARIABLE, "ShadowOut", "outBlock.",
                PNB_ROWS(ShadowBlock, PNB_SHADOW_BLOCK_MEMBERS), Names::Cpp);

    const std::string_view cull[] = {"SDSM_CULL"};
    auto culling = compileEmbeddedCompute("sdsm.comp", cull);
    ASSERT_TRUE(culling.ok()) << culling.error().message;
    expectArrayElement(culling->id(), "casters", PNB_ROWS(SdsmCasterData, PNB_SDSM_CASTER_MEMBERS));

    // The stages' working state, which the player sizes and clears.
    expectBlock(fit->id(), GL_SHADER_STORAGE_BLOCK, GL_BUFFER_VARIABLE, "SdsmState", "",
                PNB_ROWS(SdsmState, PNB_SDSM_STATE_MEMBERS));
    // The histogram view reads the same state.
    auto histogram = compileEmbeddedProgram("fullscreen.vert", "shadow_debug.frag");
    ASSERT_TRUE(histogram.ok()) << histogram.error().message;
    expectBlock(histogram->id(), GL_SHADER_STORAGE_BLOCK, GL_BUFFER_VARIABLE, "SdsmState", "",
                PNB_ROWS(SdsmState, PNB_SDSM_STATE_MEMBERS));
}

TEST(GpuLayout, LightClusterProgramsMatchTheCppStructs) {
    // The pass that writes the clusters (the player sizes their buffer from the header)...
    auto clusters = compileEmbeddedCompute("light_clusters.comp", {});
    ASSERT_TRUE(clusters.ok()) << clusters.error().message;
    expectHeaderBlock(clusters->id(), "LightClusters",
                      PNB_ROWS(LightClustersHeader, PNB_LIGHT_CLUSTERS_HEADER_MEMBERS),
                      "uClusterMasks[0]");
    // ...and the light-count debug view, which reads them and the light list's header.
    auto debug = compileEmbeddedProgram("fullscreen.vert", "debug_view.frag");
    ASSERT_TRUE(debug.ok()) << debug.error().message;
    expectHeaderBlock(debug->id(), "LightClusters",
                      PNB_ROWS(LightClustersHeader, PNB_LIGHT_CLUSTERS_HEADER_MEMBERS),
                      "uClusterMasks[0]");
    expectHeaderBlock(debug->id(), "LightBuffer",
                      PNB_ROWS(LightListHeader, PNB_LIGHT_LIST_HEADER_MEMBERS), "");
}

} // namespace
} // namespace pnb::player::test
