#include <algorithm>
#include <cstdio>

#include "load/upload.h"

namespace pnb::player {

namespace {

struct GlFormat {
    GLenum internal = GL_NONE, linearInternal = GL_NONE; // sRGB (if any) and linear
    GLenum format = GL_NONE, type = GL_NONE;             // for uncompressed uploads
    bool compressed = false;
};

GlFormat glFormat(TextureFormat f) {
    switch (f) {
    case TextureFormat::R8: return {GL_R8, GL_R8, GL_RED, GL_UNSIGNED_BYTE};
    case TextureFormat::RG8: return {GL_RG8, GL_RG8, GL_RG, GL_UNSIGNED_BYTE};
    case TextureFormat::RGB8: return {GL_SRGB8, GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE};
    case TextureFormat::RGBA8: return {GL_SRGB8_ALPHA8, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
    case TextureFormat::R16F: return {GL_R16F, GL_R16F, GL_RED, GL_HALF_FLOAT};
    case TextureFormat::RG16F: return {GL_RG16F, GL_RG16F, GL_RG, GL_HALF_FLOAT};
    case TextureFormat::RGBA16F: return {GL_RGBA16F, GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT};
    case TextureFormat::R32F: return {GL_R32F, GL_R32F, GL_RED, GL_FLOAT};
    case TextureFormat::RG32F: return {GL_RG32F, GL_RG32F, GL_RG, GL_FLOAT};
    case TextureFormat::RGBA32F: return {GL_RGBA32F, GL_RGBA32F, GL_RGBA, GL_FLOAT};
    case TextureFormat::BC1:
        return {GL_COMPRESSED_SRGB_S3TC_DXT1_EXT, GL_COMPRESSED_RGB_S3TC_DXT1_EXT, 0, 0, true};
    case TextureFormat::BC3:
        return {GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT5_EXT, GL_COMPRESSED_RGBA_S3TC_DXT5_EXT, 0, 0,
                true};
    case TextureFormat::BC4: return {GL_COMPRESSED_RED_RGTC1, GL_COMPRESSED_RED_RGTC1, 0, 0, true};
    case TextureFormat::BC5: return {GL_COMPRESSED_RG_RGTC2, GL_COMPRESSED_RG_RGTC2, 0, 0, true};
    case TextureFormat::BC7:
        return {GL_COMPRESSED_SRGB_ALPHA_BPTC_UNORM, GL_COMPRESSED_RGBA_BPTC_UNORM, 0, 0, true};
    default: return {};
    }
}

GLint glSwizzle(Swizzle s) {
    constexpr GLint k[] = {GL_RED, GL_GREEN, GL_BLUE, GL_ALPHA, GL_ZERO, GL_ONE};
    return k[size_t(s)];
}
GLint glMin(MinFilter f) {
    constexpr GLint k[] = {GL_NEAREST, GL_LINEAR, GL_NEAREST_MIPMAP_NEAREST,
                           GL_LINEAR_MIPMAP_NEAREST, GL_NEAREST_MIPMAP_LINEAR,
                           GL_LINEAR_MIPMAP_LINEAR};
    return k[size_t(f)];
}
GLint glWrap(Wrap w) {
    constexpr GLint k[] = {GL_REPEAT, GL_MIRRORED_REPEAT, GL_CLAMP_TO_EDGE};
    return k[size_t(w)];
}

} // namespace

uint64_t textureLevelBytes(const TextureDesc& desc, uint32_t level) {
    return textureLevelSizeBytes(desc.format, std::max(desc.width >> level, 1u),
                                 std::max(desc.height >> level, 1u), desc.layers);
}

PlayResult<GpuTexture> createTexture(const TextureDesc& desc, uint32_t index, uint32_t firstLevel) {
    GlFormat f = glFormat(desc.format);
    if (f.internal == GL_NONE)
        return PlayError{PlayErrorKind::Input,
                         "TEXR " + std::to_string(index) + ": unsupported texture format"};
    GLenum internal = desc.colorSpace == ColorSpace::Srgb ? f.internal : f.linearInternal;
    bool cube = desc.dimension == TextureDimension::Cube;
    // Larger than this GPU takes (a 65535-texel-wide environment drew nothing but GL errors):
    // start at the first level within its limit, and say so; refuse if none is.
    GLint limit = 0;
    glGetIntegerv(cube ? GL_MAX_CUBE_MAP_TEXTURE_SIZE : GL_MAX_TEXTURE_SIZE, &limit);
    const uint32_t asked = firstLevel;
    while (limit > 0 && firstLevel < desc.mipCount &&
           std::max(desc.width >> firstLevel, desc.height >> firstLevel) > uint32_t(limit))
        ++firstLevel;
    if (firstLevel >= desc.mipCount)
        return PlayError{PlayErrorKind::Input,
                         "TEXR " + std::to_string(index) + ": " + std::to_string(desc.width) + "x" +
                             std::to_string(desc.height) + " exceeds this GPU's texture size limit (" +
                             std::to_string(limit) + ") and has no mip level within it"};
    if (firstLevel != asked)
        std::fprintf(stderr, "pnb-play: texture %u: %ux%u exceeds this GPU's texture size limit "
                             "(%d); drawn from mip level %u (%ux%u)\n",
                     index, desc.width, desc.height, limit, firstLevel,
                     std::max(desc.width >> firstLevel, 1u), std::max(desc.height >> firstLevel, 1u));
    const uint32_t levels = desc.mipCount - firstLevel;
    GpuTexture t;
    t.texture = pnb::player::createTexture(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D);
    t.width = desc.width;
    t.height = desc.height;
    t.mipCount = desc.mipCount;
    t.firstLevel = firstLevel;
    glTextureStorage2D(t.texture.id(), GLsizei(levels), internal,
                       GLsizei(std::max(desc.width >> firstLevel, 1u)),
                       GLsizei(std::max(desc.height >> firstLevel, 1u)));
    GLint swizzle[4];
    for (int i = 0; i < 4; ++i) swizzle[i] = glSwizzle(desc.swizzle[size_t(i)]);
    glTextureParameteriv(t.texture.id(), GL_TEXTURE_SWIZZLE_RGBA, swizzle);
    glTextureParameteri(t.texture.id(), GL_TEXTURE_MIN_FILTER, glMin(desc.minFilter));
    glTextureParameteri(t.texture.id(), GL_TEXTURE_MAG_FILTER,
                        desc.magFilter == MagFilter::Nearest ? GL_NEAREST : GL_LINEAR);
    glTextureParameteri(t.texture.id(), GL_TEXTURE_WRAP_S, glWrap(desc.wrapU));
    glTextureParameteri(t.texture.id(), GL_TEXTURE_WRAP_T, glWrap(desc.wrapV));
    glTextureParameteri(t.texture.id(), GL_TEXTURE_MAX_LEVEL, GLint(levels) - 1);
    // Anisotropic filtering is a render setting (textures.anisotropy), applied by the renderer.
    t.trilinear = desc.minFilter == MinFilter::LinearMipLinear;
    for (uint32_t level = firstLevel; level < desc.mipCount; ++level) t.bytes += textureLevelBytes(desc, level);
    std::string label = "texture " + std::to_string(index);
    if (firstLevel) label += " from level " + std::to_string(firstLevel);
    glObjectLabel(GL_TEXTURE, t.texture.id(), GLsizei(label.size()), label.c_str());
    return t;
}

void uploadTextureRows(const GpuTexture& texture, const TextureDesc& desc, uint32_t level,
                       uint32_t face, uint32_t firstRow, uint32_t rows, const void* pixels) {
    GlFormat f = glFormat(desc.format);
    GLenum internal = desc.colorSpace == ColorSpace::Srgb ? f.internal : f.linearInternal;
    if (level < texture.firstLevel) return; // above this GPU's size limit (createTexture)
    const GLint glLevel = GLint(level - texture.firstLevel);
    const auto w = GLsizei(std::max(desc.width >> level, 1u));
    const auto h = GLsizei(std::max(desc.height >> level, 1u));
    rows = std::min(rows, uint32_t(h) - firstRow);
    const auto bytes = GLsizei(textureLevelSizeBytes(desc.format, uint32_t(w), rows, 1));
    if (desc.dimension == TextureDimension::Cube) {
        if (f.compressed)
            glCompressedTextureSubImage3D(texture.texture.id(), glLevel, 0, GLint(firstRow), GLint(face), w,
                                          GLsizei(rows), 1, internal, bytes, pixels);
        else
            glTextureSubImage3D(texture.texture.id(), glLevel, 0, GLint(firstRow), GLint(face), w,
                                GLsizei(rows), 1, f.format, f.type, pixels);
        return;
    }
    if (f.compressed)
        glCompressedTextureSubImage2D(texture.texture.id(), glLevel, 0, GLint(firstRow), w, GLsizei(rows),
                                      internal, bytes, pixels);
    else
        glTextureSubImage2D(texture.texture.id(), glLevel, 0, GLint(firstRow), w, GLsizei(rows), f.format,
                            f.type, pixels);
}

void uploadTextureMip(const GpuTexture& texture, const TextureDesc& desc, const TextureMip& mip) {
    const uint64_t faceBytes = mip.data.size() / desc.layers;
    for (uint32_t face = 0; face < desc.layers; ++face)
        uploadTextureRows(texture, desc, mip.level, face, 0, mip.height, mip.data.data() + face * faceBytes);
}

} // namespace pnb::player
