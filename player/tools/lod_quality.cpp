// pnb-play --lod-metrics: selected levels of detail against full detail, same view (lod_quality.h).
#include "lod_quality.h"

#include <algorithm>
#include <cmath>

namespace pnb::player {

PlayResult<std::vector<std::pair<std::string, double>>> measureLodQuality(Renderer& renderer, bool followUp,
                                                                          LodFrame* last) {
    std::vector<std::pair<std::string, double>> out;
    if (followUp) return out;
    const uint64_t lodTriangles = renderer.lastFrame().triangles;
    auto selected = renderer.capture(CaptureBuffer::Color);
    if (!selected) return selected.error();
    const RenderSettings settings = renderer.settings();
    RenderSettings full = settings;
    full.lodForce = 0;
    renderer.setSettings(full);
    auto r = renderer.render(renderer.lastCamera(), selected->width, selected->height);
    const uint64_t fullTriangles = renderer.lastFrame().triangles;
    auto reference = r ? renderer.capture(CaptureBuffer::Color) : PlayResult<CapturedImage>(r.error());
    renderer.setSettings(settings);
    if (!reference) return reference.error();
    double squared = 0;
    size_t over = 0, pixels = size_t(selected->width) * selected->height;
    std::vector<uint8_t> worstOf(pixels);
    for (size_t p = 0; p < pixels; ++p) {
        int worst = 0;
        for (size_t c = 0; c < 3; ++c) {
            int d = int(selected->u8[p * 4 + c]) - int(reference->u8[p * 4 + c]);
            squared += double(d * d);
            worst = std::max(worst, std::abs(d));
        }
        over += worst > 8;
        worstOf[p] = uint8_t(worst);
    }
    if (last) *last = {selected->width, selected->height, std::move(worstOf)};
    const double mse = squared / double(std::max<size_t>(pixels * 3, 1));
    const double psnr = mse > 0 ? std::min(100.0, 10.0 * std::log10(255.0 * 255.0 / mse)) : 100.0;
    out.emplace_back("lod_psnr_db", psnr);
    out.emplace_back("lod_pixels_over8_pct", 100.0 * double(over) / double(std::max<size_t>(pixels, 1)));
    out.emplace_back("lod_triangles", double(lodTriangles));
    out.emplace_back("full_triangles", double(fullTriangles));
    out.emplace_back("lod_triangle_ratio", fullTriangles ? double(lodTriangles) / double(fullTriangles) : 1.0);
    return out;
}

} // namespace pnb::player
