// pnb-expand-shaders OUT_DIR: writes every real shader program as the GPU driver receives it, for
// glslangValidator (validate_shaders.sh). Scene programs: every variant the converter can pack,
// found by asking its own planner (planShaders) about every material feature set, shading path,
// alpha mode and scene need; each stage resolved by its own #include resolver
// (resolveShaderSource, the container's SHDR text). Player programs: player_programs.h's table
// over the embedded player/shaders. Defines go after the #version line, as the player's
// compileProgram puts them.
//
// Writes OUT_DIR/stages/N.{vert,frag,geom,comp} (each distinct stage text once) and
// OUT_DIR/programs.tsv: "label<TAB>stage paths separated by spaces", one program a line.
// Exit 1 when a file of shaders/ or player/shaders/ is in no program (it would go unvalidated)
// or a source does not resolve.
//
// A define whose name does not occur in a stage's resolved text is left out of that stage's file:
// the preprocessor never reads it, so the compile is the same, and the stage texts of the ~4600
// scene programs shrink to the distinct ones (surface.vert, for one, reads 4 of the 13 defines).

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "player_programs.h"
#include "player_shaders_for_tests.h" // generated: kPlayerShaders, player/shaders embedded
#include "pnb_converter/shader_permutations.h"

namespace fs = std::filesystem;
using namespace pnb;
using namespace pnb::converter;
using pnb::test::PlayerProgram;
using pnb::test::ShaderOrigin;

namespace {

// A program ready to write: its label and, per stage, the file name and the text before defines.
struct ExpandedProgram {
    std::string label;
    std::vector<std::string> files;
    std::vector<std::string> texts;
    std::vector<std::string> defines;
};

// Every variant planShaders can return: one material at a time, over every combination of the
// MaterialFeatures flags (alphaMask follows the alpha mode, as material_resolve.cpp sets it), the
// shading path, alpha mode and shadow receiving, and every SceneShaderNeeds.
std::vector<ProgramVariant> everySceneVariant() {
    std::map<std::string, ProgramVariant> variants; // by describeVariant: sorted, deduplicated
    for (uint32_t bits = 0; bits < 256; ++bits)
        for (int path = 0; path < int(ShadingPath::Count); ++path)
            for (int alpha = 0; alpha < int(AlphaMode::Count); ++alpha)
                for (uint32_t flags = 0; flags < 2 * 16; ++flags) {
                    Material m;
                    m.shadingPath = ShadingPath(path);
                    m.alphaMode = AlphaMode(alpha);
                    m.receivesShadows = flags & 1;
                    MaterialFeatures f;
                    f.baseColorMap = bits & 1;
                    f.metallicRoughnessMap = bits & 2;
                    f.normalMap = bits & 4;
                    f.occlusionMap = bits & 8;
                    f.emissiveMap = bits & 16;
                    f.vertexColor = bits & 32;
                    f.uv0 = bits & 64;
                    f.uv1 = bits & 128;
                    f.alphaMask = m.alphaMode == AlphaMode::Mask;
                    SceneShaderNeeds needs;
                    needs.shadows = flags & 2;
                    needs.maskedCasters = flags & 4;
                    needs.gi = flags & 8;
                    needs.ibl = flags & 16;
                    ShaderPlan plan = planShaders(std::span(&m, 1), std::span(&f, 1), needs);
                    for (ProgramVariant& v : plan.programs) variants.emplace(describeVariant(v), v);
                }
    // The deform pass's variants (skins, morph targets or both) do not depend on the materials.
    for (int deforms = 1; deforms < 4; ++deforms) {
        Material m;
        MaterialFeatures f;
        SceneShaderNeeds needs;
        needs.skins = deforms & 1;
        needs.morphs = deforms & 2;
        for (ProgramVariant& v : planShaders(std::span(&m, 1), std::span(&f, 1), needs).programs)
            variants.emplace(describeVariant(v), v);
    }
    std::vector<ProgramVariant> out;
    for (auto& [label, v] : variants) out.push_back(std::move(v));
    return out;
}

std::string_view playerSource(std::string_view name) {
    for (const EmbeddedFile& f : kPlayerShaders)
        if (f.name == name) return f.text;
    return {};
}

// Whether `name` occurs in `text` as a whole identifier.
bool mentions(const std::string& text, const std::string& name) {
    auto isIdent = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    for (size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
        bool startOk = at == 0 || !isIdent(text[at - 1]);
        size_t end = at + name.size();
        if (startOk && (end == text.size() || !isIdent(text[end]))) return true;
    }
    return false;
}

// program_compile.cpp's withDefines: "#define NAME" (NAME=VALUE as "NAME VALUE") after line 1.
std::string withDefines(const std::string& source, const std::vector<std::string>& defines) {
    size_t eol = source.find('\n');
    std::string text = source.substr(0, eol) + "\n";
    for (std::string d : defines) {
        if (size_t eq = d.find('='); eq != std::string::npos) d[eq] = ' ';
        text += "#define " + d + "\n";
    }
    if (eol != std::string::npos) text += source.substr(eol + 1);
    return text;
}

struct Expander {
    std::set<std::string> usedScene, usedPlayer; // files some program reads, with its includes
    std::vector<ExpandedProgram> programs;
    std::vector<std::string> errors;

    // The container's text of scene stage `file` (includes inlined), noting every file it read.
    bool sceneText(const std::string& file, std::string& text) {
        auto resolved = resolveShaderSource(file, builtinShaderFiles());
        if (!resolved) {
            errors.push_back(file + ": " + resolved.error().message);
            return false;
        }
        usedScene.insert(resolved->files.begin(), resolved->files.end());
        text = resolved->text;
        return true;
    }

    void addScene(const ProgramVariant& v) {
        ExpandedProgram p{describeVariant(v), v.stageFiles, {}, v.defines};
        for (const std::string& f : v.stageFiles)
            if (!sceneText(f, p.texts.emplace_back())) return;
        programs.push_back(std::move(p));
    }

    void addPlayer(const PlayerProgram& program) {
        ExpandedProgram p{program.label, {}, {}, program.defines};
        for (const pnb::test::PlayerStage& s : program.stages) {
            p.files.push_back(s.file);
            if (s.origin == ShaderOrigin::Scene) {
                if (!sceneText(s.file, p.texts.emplace_back())) return;
                continue;
            }
            std::string_view text = playerSource(s.file);
            if (text.empty()) {
                errors.push_back(program.label + ": " + s.file + " is not in player/shaders");
                return;
            }
            usedPlayer.insert(s.file);
            p.texts.emplace_back(text);
        }
        programs.push_back(std::move(p));
    }

    // The block headers (shaders/shared/) reach the player's built-in programs inlined at build
    // time (cmake/embed_text.cmake), #include lines gone: one is in a player program when its
    // include guard (PNB_SHARED_<NAME>_H) is in the program's text.
    bool inlinedInPlayerProgram(std::string_view file) const {
        if (!file.starts_with("shared/") || !file.ends_with(".h")) return false;
        std::string guard = "PNB_SHARED_" + std::string(file.substr(7, file.size() - 9)) + "_H";
        for (char& c : guard) c = char(std::toupper(static_cast<unsigned char>(c)));
        for (const ExpandedProgram& p : programs)
            for (const std::string& text : p.texts)
                if (text.find("#define " + guard) != std::string::npos) return true;
        return false;
    }

    // Files of either library that no program reads: they would pass unvalidated.
    void checkCoverage() {
        for (const ShaderFile& f : builtinShaderFiles())
            if (!usedScene.count(std::string(f.name)) && !inlinedInPlayerProgram(f.name))
                errors.push_back("shaders/" + std::string(f.name) +
                                 " is in no program the converter can pack: validate it or remove it");
        for (const EmbeddedFile& f : kPlayerShaders)
            if (!usedPlayer.count(std::string(f.name)))
                errors.push_back("player/shaders/" + std::string(f.name) +
                                 " is in no program of tests/shaders/player_programs.cpp: add its call site");
    }
};

// glslang 12 does not know GL_NV_shader_atomic_float (lpv_inject.comp with FLOAT_ATOMICS requires
// it) and stops at the #extension line, which would leave the rest of the stage unchecked. Its
// EXT twin declares the same atomicAdd(float) on buffer variables, so the stage is validated
// under that name; the note says so. Drop this once Debian's glslang knows the NV extension.
std::string glslangSpelling(std::string text, const ExpandedProgram& p, std::set<std::string>& notes) {
    const std::string nv = "GL_NV_shader_atomic_float", ext = "GL_EXT_shader_atomic_float";
    // Only where FLOAT_ATOMICS turns the #extension line on; elsewhere the text stays exact.
    if (std::find(p.defines.begin(), p.defines.end(), "FLOAT_ATOMICS") == p.defines.end()) return text;
    for (size_t at = text.find(nv); at != std::string::npos; at = text.find(nv, at)) {
        text.replace(at, nv.size(), ext);
        notes.insert(p.label);
    }
    return text;
}

// Writes each distinct stage text once and programs.tsv. Returns the number of stage files.
size_t writePrograms(const fs::path& out, const std::vector<ExpandedProgram>& programs,
                     std::set<std::string>& notes) {
    fs::create_directories(out / "stages");
    std::map<std::string, std::string> pathOf; // stage text (with extension) -> its file
    std::ofstream table(out / "programs.tsv");
    for (const ExpandedProgram& p : programs) {
        table << p.label << "\t";
        for (size_t i = 0; i < p.files.size(); ++i) {
            std::vector<std::string> read;
            for (const std::string& d : p.defines)
                if (mentions(p.texts[i], d.substr(0, d.find('=')))) read.push_back(d);
            const std::string ext = fs::path(p.files[i]).extension().string();
            const std::string text = glslangSpelling(withDefines(p.texts[i], read), p, notes);
            auto [it, added] = pathOf.emplace(ext + "\n" + text, std::string());
            if (added) {
                it->second = (out / "stages" / (std::to_string(pathOf.size()) + ext)).string();
                std::ofstream(it->second, std::ios::binary) << text;
            }
            table << (i ? " " : "") << it->second;
        }
        table << "\n";
    }
    return pathOf.size();
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: pnb-expand-shaders OUT_DIR\n");
        return 2;
    }
    Expander e;
    const std::vector<ProgramVariant> scene = everySceneVariant();
    for (const ProgramVariant& v : scene) {
        e.addScene(v);
        if (v.name == "shadow") e.addPlayer(pnb::test::geometryLayerProgram(describeVariant(v), v.defines));
    }
    for (const PlayerProgram& p : pnb::test::playerPrograms()) e.addPlayer(p);
    e.checkCoverage();
    for (const std::string& error : e.errors) std::fprintf(stderr, "pnb-expand-shaders: %s\n", error.c_str());
    if (!e.errors.empty()) return 1;
    std::set<std::string> notes;
    const size_t stages = writePrograms(argv[1], e.programs, notes);
    for (const std::string& label : notes)
        std::printf("note: %s is checked with GL_EXT_shader_atomic_float for GL_NV_shader_atomic_float "
                    "(glslang lacks the NV extension)\n", label.c_str());
    std::printf("%zu programs (%zu scene variants), %zu distinct stage texts in %s\n", e.programs.size(),
                scene.size(), stages, argv[1]);
    return 0;
}
