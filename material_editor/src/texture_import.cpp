// Importing an image file as a new texture, processed by the converter's texture pipeline with
// the converter's defaults (full mip chain filtered in linear light, no resizing, no block
// compression, constant channels dropped into the swizzle).

#include <filesystem>

#include "document_impl.h"
#include "pnb_converter/texture_processing.h"

namespace pnb::editor {

Result<uint32_t> Document::importTexture(const std::string& imagePath, bool srgb,
                                         std::string_view name, uint64_t maxMemoryBytes) {
    Impl& d = *mImpl;
    const size_t count = d.base.textures + d.current.imported.size();
    auto taken = [&](std::string_view n) {
        for (uint32_t t = 0; t < count; ++t)
            if (d.textureName(t, d.current) == n) return true;
        return false;
    };
    std::string finalName(name);
    if (finalName.empty()) {
        std::string stem = std::filesystem::path(imagePath).stem().string();
        if (stem.empty()) stem = "texture";
        finalName = stem;
        for (int k = 2; taken(finalName); ++k) finalName = stem + "-" + std::to_string(k);
    } else if (taken(finalName)) {
        return makeError(FormatError::BadReference, 0,
                         "a texture named '%s' already exists; textures: %s", finalName.c_str(),
                         d.textureList(count, d.current).c_str());
    }

    converter::IrImage image;
    image.name = finalName;
    image.path = imagePath;
    converter::TextureRequest request;
    request.image = &image;
    request.name = finalName;
    request.colorSpace = srgb ? ColorSpace::Srgb : ColorSpace::Linear;
    // Every channel may be read by some slot; constant ones become a swizzle anyway.
    converter::TextureSettings settings;
    settings.jobs = 1;
    settings.maxMemoryBytes = maxMemoryBytes;
    auto processed = converter::processTextures({request}, settings);
    if (!processed)
        return makeError(FormatError::IoError, 0, "cannot import '%s': %s", imagePath.c_str(),
                         processed.error().message.c_str());
    converter::ProcessedTexture& t = processed->front();
    auto imported = std::make_shared<detail::ImportedTexture>();
    imported->name = finalName;
    imported->desc = t.desc;
    imported->levels = std::move(t.levels);

    auto list = d.current.imported;
    list.push_back(std::move(imported));
    auto next = d.makeState(d.current.materials, std::move(list));
    if (!next) return next.error();
    d.pushState(std::move(*next), false);
    return uint32_t(count);
}

} // namespace pnb::editor
