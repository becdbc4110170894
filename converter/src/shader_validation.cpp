// Conversion-time GLSL validation with glslang: a broken shader fails the conversion, not the
// player. Each variant is compiled with its defines inserted exactly where the player inserts
// them (after the #version line) and linked, so interface mismatches between stages show too.
//
// A variant glslang accepted is remembered under a hash of everything its verdict depends on
// (shader_validation_cache.h), so the ~0.1 s glslang spends per conversion is paid once per
// distinct program text, not once per run.

#include <xxhash.h>

#include <cstdio>
#include <memory>
#include <mutex>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/build_info.h>

#include "pnb_converter/shader_permutations.h"
#include "pnb_converter/shader_validation_cache.h"

namespace pnb::converter {

namespace {

EShLanguage languageOf(ShaderStage s) {
    switch (s) {
    case ShaderStage::Vertex: return EShLangVertex;
    case ShaderStage::Fragment: return EShLangFragment;
    case ShaderStage::Geometry: return EShLangGeometry;
    case ShaderStage::Compute: return EShLangCompute;
    case ShaderStage::TessControl: return EShLangTessControl;
    case ShaderStage::TessEvaluation: return EShLangTessEvaluation;
    case ShaderStage::Count: break;
    }
    return EShLangVertex;
}

// glslang reports "ERROR: 3:12: ..." with 3 = the #line source-string number; name the file.
std::string nameFiles(std::string log, const std::vector<std::string>& files) {
    std::string out;
    size_t pos = 0;
    while (pos < log.size()) {
        size_t end = log.find('\n', pos);
        if (end == std::string::npos) end = log.size();
        std::string line = log.substr(pos, end - pos);
        pos = end + 1;
        size_t colon = line.find(": ");
        if (colon != std::string::npos) {
            size_t numStart = colon + 2, numEnd = line.find(':', numStart);
            if (numEnd != std::string::npos) {
                std::string num = line.substr(numStart, numEnd - numStart);
                if (!num.empty() && num.find_first_not_of("0123456789") == std::string::npos) {
                    size_t k = std::stoul(num);
                    if (k < files.size()) line = line.substr(0, numStart) + files[k] +
                                                 line.substr(numEnd);
                }
            }
        }
        if (!line.empty()) out += (out.empty() ? "" : "\n") + line;
    }
    return out;
}

std::string withDefines(const std::string& source, const std::vector<std::string>& defines) {
    size_t eol = source.find('\n');
    std::string text = source.substr(0, eol + 1);
    for (const std::string& d : defines) {
        size_t eq = d.find('=');
        text += "#define " + (eq == std::string::npos ? d : d.substr(0, eq) + " " + d.substr(eq + 1)) +
                "\n";
    }
    return text + source.substr(eol + 1);
}

// Everything a verdict depends on besides the texts: the glslang build (its header version
// and the library's own, in case the two differ) and how validate() calls it below. Change
// "settings" when the call changes, so that old verdicts stop matching.
std::string validatorIdentity() {
    const glslang::Version v = glslang::GetVersion();
    char text[160];
    std::snprintf(text, sizeof(text),
                  "glslang %d.%d.%d%s (headers %d.%d.%d%s); settings: GLSL 450 core, OpenGL 450, "
                  "default resources, EShMsgDefault",
                  v.major, v.minor, v.patch, v.flavor ? v.flavor : "", GLSLANG_VERSION_MAJOR,
                  GLSLANG_VERSION_MINOR, GLSLANG_VERSION_PATCH, GLSLANG_VERSION_FLAVOR);
    return text;
}

// XXH3-128 over the identity and, per stage, its kind, file name and exact text, each
// length-prefixed so that no two different inputs hash the same bytes. 32 hex digits.
std::string validationKey(const ProgramVariant& v, const std::vector<std::string>& texts) {
    static const std::string identity = validatorIdentity();
    XXH3_state_t* state = XXH3_createState();
    XXH3_128bits_reset(state);
    auto add = [&](const std::string& s) {
        uint64_t n = s.size();
        XXH3_128bits_update(state, &n, sizeof(n));
        XXH3_128bits_update(state, s.data(), s.size());
    };
    add(identity);
    for (size_t i = 0; i < texts.size(); ++i) {
        add(std::to_string(int(v.stages[i])));
        add(v.stageFiles[i]);
        add(texts[i]);
    }
    XXH128_hash_t h = XXH3_128bits_digest(state);
    XXH3_freeState(state);
    char hex[33];
    std::snprintf(hex, sizeof(hex), "%016llx%016llx", (unsigned long long)h.high64,
                  (unsigned long long)h.low64);
    return hex;
}

} // namespace

Result<size_t, ConvertError> validateShaders(const ShaderPlan& plan,
                                             std::span<const ShaderFile> library,
                                             ShaderValidationCache* cache,
                                             ShaderValidationStats* stats) {
    for (const ProgramVariant& v : plan.programs) {
        std::vector<std::string> texts;
        std::vector<ResolvedSource> sources;
        for (size_t i = 0; i < v.stageFiles.size(); ++i) {
            auto resolved = resolveShaderSource(v.stageFiles[i], library);
            if (!resolved)
                return ConvertError{ConvertErrorKind::Input,
                                    describeVariant(v) + ": " + resolved.error().message};
            texts.push_back(withDefines(resolved->text, v.defines));
            sources.push_back(std::move(*resolved));
        }
        const std::string key = cache ? validationKey(v, texts) : std::string();
        if (cache && cache->contains(key)) {
            if (stats) ++stats->fromCache;
            continue;
        }
        // glslang's process-wide state is initialised once, on the first compile, and kept (it
        // is not reference counted safely across threads in all versions).
        static std::once_flag once;
        std::call_once(once, [] { glslang::InitializeProcess(); });
        std::vector<std::unique_ptr<glslang::TShader>> shaders;
        glslang::TProgram program;
        for (size_t i = 0; i < v.stageFiles.size(); ++i) {
            const std::string& text = texts[i];
            auto shader = std::make_unique<glslang::TShader>(languageOf(v.stages[i]));
            const char* strings[] = {text.c_str()};
            const char* names[] = {v.stageFiles[i].c_str()};
            shader->setStringsWithLengthsAndNames(strings, nullptr, names, 1);
            shader->setEnvInput(glslang::EShSourceGlsl, languageOf(v.stages[i]),
                                glslang::EShClientOpenGL, 450);
            shader->setEnvClient(glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450);
            if (!shader->parse(GetDefaultResources(), 450, ECoreProfile, false, false,
                               EShMsgDefault))
                return ConvertError{ConvertErrorKind::Input,
                                    "shader " + describeVariant(v) + " (" + v.stageFiles[i] +
                                        ") does not compile:\n" +
                                        nameFiles(shader->getInfoLog(), sources[i].files)};
            program.addShader(shader.get());
            shaders.push_back(std::move(shader));
        }
        if (!program.link(EShMsgDefault))
            return ConvertError{ConvertErrorKind::Input, "shader " + describeVariant(v) +
                                                             " does not link:\n" +
                                                             program.getInfoLog()};
        if (stats) ++stats->compiled;
        if (cache) cache->remember(key);
    }
    return plan.programs.size();
}

} // namespace pnb::converter
