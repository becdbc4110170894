// summary_json.cpp — the ConvertSummary as JSON (see summary_json.h).
#include "summary_json.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "pnb_converter/environment.h"

namespace pnb::converter {

std::string summaryJson(const ConvertSettings& s, const ConvertSummary& r) {
    using nlohmann::json;
    json stages = json::object();
    double total = 0;
    for (const StageTiming& st : r.stages) {
        stages[st.stage] = st.seconds;
        total += st.seconds;
    }
    json j = {
        {"output", s.output},
        {"output_bytes", r.outputBytes},
        {"mesh_bytes", r.meshBytes},
        {"texture_bytes", r.textureBytes},
        {"counts", {{"meshes", r.meshes}, {"submeshes", r.submeshes}, {"nodes", r.nodes},
                    {"materials", r.materials}, {"textures", r.textures}, {"lights", r.lights},
                    {"cameras", r.cameras}, {"camera_paths", r.cameraPaths},
                    {"instances", r.instances}}},
        {"triangles_in", r.inputTriangles},
        {"triangles_out", r.outputTriangles},
        {"vertices_in", r.inputVertices},
        {"vertices_out", r.outputVertices},
        // null, not 0, when the option was off: "no error" and "not quantised" differ.
        {"quantized", s.mesh.quantize},
        {"max_position_error", s.mesh.quantize ? json(r.maxPositionError) : json(nullptr)},
        {"max_normal_error_deg",
         s.mesh.quantize ? json(double(r.maxNormalErrorRadians) * 57.29577951308232) : json(nullptr)},
        {"lod_errors", r.lodErrors},
        {"min_texture_psnr_db", r.minTexturePsnrDb > 0 ? json(r.minTexturePsnrDb) : json(nullptr)},
        {"programs", r.programs},
        {"omitted", r.omitted},
        {"warnings", r.warnings},
        {"not_rendered", r.notRendered},
        // What the converter added, flagged generated in the container (not warnings):
        // "default sun", "default environment", "default camera", "default orbit".
        {"added", addedDefaults(r)},
        {"stage_seconds", stages},
        {"seconds", total},
    };
    if (r.environment) {
        const EnvironmentSummary& e = *r.environment;
        j["environment"] = {{"name", e.name},
                            {"generated", e.generated},
                            {"radiance", {e.radianceWidth, e.radianceHeight}},
                            {"specular_size", e.specularSize},
                            {"specular_levels", e.specularLevels},
                            {"bytes", e.bytes},
                            {"cleaned_texels", e.cleanedTexels},
                            {"seconds", e.seconds}};
    }
    return j.dump(1) + "\n";
}

std::string writeSummaryJson(const std::string& path, const ConvertSettings& settings,
                             const ConvertSummary& summary) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f << summaryJson(settings, summary);
        f.flush();
        if (!f) {
            std::error_code ignored;
            std::filesystem::remove(tmp, ignored);
            return path + ": cannot write the summary";
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        return path + ": cannot write the summary (" + ec.message() + ")";
    }
    return {};
}

} // namespace pnb::converter
