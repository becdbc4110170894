#include "gl/program_compile.h"

#include <chrono>
#include <cstdlib>
#include <sstream>

#include "player_shaders.h"
#include "pnb_player/program_cache.h"

namespace pnb::player {

namespace {

std::string_view stageName(GLenum stage) {
    switch (stage) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_FRAGMENT_SHADER: return "fragment";
    case GL_GEOMETRY_SHADER: return "geometry";
    case GL_COMPUTE_SHADER: return "compute";
    case GL_TESS_CONTROL_SHADER: return "tessellation control";
    case GL_TESS_EVALUATION_SHADER: return "tessellation evaluation";
    default: return "unknown";
    }
}

GLenum glStage(ShaderStage s) {
    switch (s) {
    case ShaderStage::Vertex: return GL_VERTEX_SHADER;
    case ShaderStage::Fragment: return GL_FRAGMENT_SHADER;
    case ShaderStage::Geometry: return GL_GEOMETRY_SHADER;
    case ShaderStage::Compute: return GL_COMPUTE_SHADER;
    case ShaderStage::TessControl: return GL_TESS_CONTROL_SHADER;
    case ShaderStage::TessEvaluation: return GL_TESS_EVALUATION_SHADER;
    default: return GL_NONE;
    }
}

// The `// pnb-files:` table on line 2, if present.
std::vector<std::string> fileTable(std::string_view source) {
    std::vector<std::string> files;
    size_t line2 = source.find('\n');
    if (line2 == std::string_view::npos) return files;
    std::string_view rest = source.substr(line2 + 1);
    constexpr std::string_view kPrefix = "// pnb-files:";
    if (rest.substr(0, kPrefix.size()) != kPrefix) return files;
    std::istringstream in(std::string(rest.substr(kPrefix.size(), rest.find('\n') - kPrefix.size())));
    for (std::string f; in >> f;) files.push_back(f);
    return files;
}

// Mesa and NVIDIA write "F:L(C): ..." / "F(L) : ..." where F is the #line file number; rewrite
// the leading number as the file name so the message points into shaders/.
std::string annotateLog(const std::string& log, const std::vector<std::string>& files) {
    std::istringstream in(log);
    std::string out;
    for (std::string line; std::getline(in, line);) {
        char* end = nullptr;
        long file = std::strtol(line.c_str(), &end, 10);
        if (end != line.c_str() && (*end == ':' || *end == '(') && file >= 0 &&
            size_t(file) < files.size())
            line = files[size_t(file)] + end;
        out += "  " + line + "\n";
    }
    return out;
}

std::string withDefines(std::string_view source, std::span<const std::string_view> defines) {
    size_t firstLine = source.find('\n');
    if (firstLine == std::string_view::npos) firstLine = source.size();
    std::string text(source.substr(0, firstLine));
    text += "\n";
    for (std::string_view d : defines) {
        std::string def(d);
        size_t eq = def.find('=');
        if (eq != std::string::npos) def[eq] = ' ';
        text += "#define " + def + "\n";
    }
    if (firstLine < source.size()) text.append(source.substr(firstLine + 1));
    return text;
}

std::string infoLog(GLuint object, bool program) {
    GLint length = 0;
    if (program) glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
    else glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    if (program) glGetProgramInfoLog(object, length, nullptr, log.data());
    else glGetShaderInfoLog(object, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

} // namespace

PlayResult<GlHandle> compileProgram(std::string_view label, std::span<const StageSource> stages,
                                    std::span<const std::string_view> defines) {
    const auto start = std::chrono::steady_clock::now();
    struct Timed { // every return path adds its time to the start-up figures
        std::chrono::steady_clock::time_point start;
        ~Timed() { addProgramTime(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()); }
    } timed{start};
    std::vector<std::string> texts;
    std::vector<ProgramStageText> keyed;
    texts.reserve(stages.size());
    for (const StageSource& s : stages) {
        texts.push_back(withDefines(s.source, defines));
        keyed.push_back({s.stage, texts.back()});
    }
    const ProgramCacheLookup cache = programCacheLookup(keyed);
    if (GLuint cached = loadCachedProgram(cache, label)) {
        glObjectLabel(GL_PROGRAM, cached, GLsizei(label.size()), label.data());
        return GlHandle(GlKind::Program, cached);
    }
    countCompiledProgram(cache);

    GlHandle program(GlKind::Program, glCreateProgram());
    std::vector<GlHandle> shaders;
    for (size_t i = 0; i < stages.size(); ++i) {
        const StageSource& s = stages[i];
        GlHandle shader(GlKind::Shader, glCreateShader(s.stage));
        const char* ptr = texts[i].c_str();
        glShaderSource(shader.id(), 1, &ptr, nullptr);
        glCompileShader(shader.id());
        GLint ok = GL_FALSE;
        glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
        if (!ok)
            return PlayError{PlayErrorKind::Gl,
                             "program " + std::string(label) + ": " +
                                 std::string(stageName(s.stage)) + " stage does not compile:\n" +
                                 annotateLog(infoLog(shader.id(), false), fileTable(s.source))};
        glAttachShader(program.id(), shader.id());
        shaders.push_back(std::move(shader));
    }
    prepareProgramForCache(cache, program.id());
    glLinkProgram(program.id());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok)
        return PlayError{PlayErrorKind::Gl, "program " + std::string(label) +
                                                " does not link:\n" +
                                                annotateLog(infoLog(program.id(), true), {})};
    for (const GlHandle& s : shaders) glDetachShader(program.id(), s.id());
    glObjectLabel(GL_PROGRAM, program.id(), GLsizei(label.size()), label.data());
    storeCachedProgram(cache, program.id());
    return program;
}

std::string programLabel(const Scene& scene, uint32_t index) {
    const Program& p = scene.programs[index];
    std::string label(scene.str(p.name));
    if (p.defines.empty()) return label;
    label += "[";
    for (size_t i = 0; i < p.defines.size(); ++i)
        label += (i ? " " : "") + std::string(scene.str(p.defines[i]));
    return label + "]";
}

PlayResult<GlHandle> compileSceneProgram(const Scene& scene, uint32_t index) {
    const Program& p = scene.programs[index];
    std::vector<StageSource> stages;
    for (uint32_t s : p.shaders) {
        const ShaderSource& src = scene.shaders[s];
        GLenum stage = glStage(src.stage);
        if (stage == GL_NONE)
            return PlayError{PlayErrorKind::Input, "PROG " + std::to_string(index) +
                                                       ": shader stage out of range"};
        stages.push_back({stage, std::string_view(reinterpret_cast<const char*>(src.source.data()),
                                                  src.source.size())});
    }
    std::vector<std::string_view> defines;
    for (StringRef d : p.defines) defines.push_back(scene.str(d));
    return compileProgram(programLabel(scene, index) + " (PROG " + std::to_string(index) + ")",
                          stages, defines);
}

std::string_view embeddedSource(std::string_view name) {
    for (const EmbeddedFile& f : kPlayerShaders)
        if (f.name == name) return f.text;
    return {};
}

PlayResult<GlHandle> compileEmbeddedCompute(std::string_view file,
                                            std::span<const std::string_view> defines) {
    StageSource stage{GL_COMPUTE_SHADER, embeddedSource(file)};
    std::string label = std::string(file);
    for (std::string_view d : defines) label += " " + std::string(d);
    label += " (built in)";
    if (stage.source.empty())
        return PlayError{PlayErrorKind::Gl, "program " + label + ": source not embedded"};
    return compileProgram(label, std::span(&stage, 1), defines);
}

PlayResult<GlHandle> compileEmbeddedProgram(std::string_view vertexFile,
                                            std::string_view fragmentFile,
                                            std::span<const std::string_view> defines) {
    StageSource stages[] = {{GL_VERTEX_SHADER, embeddedSource(vertexFile)},
                            {GL_FRAGMENT_SHADER, embeddedSource(fragmentFile)}};
    std::string label = std::string(fragmentFile) + " (built in)";
    if (stages[0].source.empty() || stages[1].source.empty())
        return PlayError{PlayErrorKind::Gl, "program " + label + ": source not embedded"};
    return compileProgram(label, stages, defines);
}

} // namespace pnb::player
