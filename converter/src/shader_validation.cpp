// Conversion-time GLSL validation with glslang: a broken shader fails the conversion, not the
// player. Each variant is compiled with its defines inserted exactly where the player inserts
// them (after the #version line) and linked, so interface mismatches between stages show too.

#include <memory>
#include <mutex>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include "pnb_converter/shader_permutations.h"

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

} // namespace

Result<size_t, ConvertError> validateShaders(const ShaderPlan& plan,
                                             std::span<const ShaderFile> library) {
    // glslang's process-wide state is initialised once and kept (it is not reference counted
    // safely across threads in all versions).
    static std::once_flag once;
    std::call_once(once, [] { glslang::InitializeProcess(); });

    for (const ProgramVariant& v : plan.programs) {
        std::vector<std::unique_ptr<glslang::TShader>> shaders;
        glslang::TProgram program;
        for (size_t i = 0; i < v.stageFiles.size(); ++i) {
            auto resolved = resolveShaderSource(v.stageFiles[i], library);
            if (!resolved)
                return ConvertError{ConvertErrorKind::Input,
                                    describeVariant(v) + ": " + resolved.error().message};
            std::string text = withDefines(resolved->text, v.defines);
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
                                        nameFiles(shader->getInfoLog(), resolved->files)};
            program.addShader(shader.get());
            shaders.push_back(std::move(shader));
        }
        if (!program.link(EShMsgDefault))
            return ConvertError{ConvertErrorKind::Input, "shader " + describeVariant(v) +
                                                             " does not link:\n" +
                                                             program.getInfoLog()};
    }
    return plan.programs.size();
}

} // namespace pnb::converter
