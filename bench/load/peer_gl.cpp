// The shared GL side of the peer loaders (see peer_gl.h).
#include "peer_gl.h"

#include <algorithm>

namespace pnb::bench {

namespace {

constexpr const char* kVertexSource = R"(
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv0;
uniform mat4 uViewProjection;
uniform mat4 uModel;
out vec3 vWorld;
out vec3 vNormal;
out vec2 vUv0;
void main() {
    vec4 world = uModel * vec4(inPosition, 1.0);
    vWorld = world.xyz;
#ifdef HAS_NORMALS
    vNormal = mat3(uModel) * inNormal;
#else
    vNormal = vec3(0.0);
#endif
#ifdef HAS_UV0
    vUv0 = inUv0;
#else
    vUv0 = vec2(0.0);
#endif
    gl_Position = uViewProjection * world;
}
)";

constexpr const char* kFragmentSource = R"(
in vec3 vWorld;
in vec3 vNormal;
in vec2 vUv0;
uniform vec4 uBaseColorFactor;
uniform vec3 uLightDirection;
uniform float uAlphaCutoff;
layout(binding = 0) uniform sampler2D uBaseColor;
layout(binding = 1) uniform sampler2D uNormalMap;
out vec4 outColor;

// Tangent frame from screen-space derivatives (no tangent stream needed).
mat3 cotangentFrame(vec3 n, vec3 p, vec2 uv) {
    vec3 dp1 = dFdx(p), dp2 = dFdy(p);
    vec2 duv1 = dFdx(uv), duv2 = dFdy(uv);
    vec3 dp2perp = cross(dp2, n), dp1perp = cross(n, dp1);
    vec3 t = dp2perp * duv1.x + dp1perp * duv2.x;
    vec3 b = dp2perp * duv1.y + dp1perp * duv2.y;
    float invmax = inversesqrt(max(dot(t, t), dot(b, b)) + 1e-20);
    return mat3(t * invmax, b * invmax, n);
}

void main() {
#ifdef HAS_NORMALS
    vec3 n = normalize(vNormal);
#else
    vec3 n = normalize(cross(dFdx(vWorld), dFdy(vWorld)));
#endif
    vec4 base = uBaseColorFactor;
#ifdef BASE_COLOR_MAP
    base *= texture(uBaseColor, vUv0);
#endif
#ifdef ALPHA_MASK
    if (base.a < uAlphaCutoff) discard;
#endif
#ifdef NORMAL_MAP
    vec3 tn = texture(uNormalMap, vUv0).xyz * 2.0 - 1.0;
    n = normalize(cotangentFrame(n, vWorld, vUv0) * tn);
#endif
    float diffuse = max(dot(n, -normalize(uLightDirection)), 0.0);
    outColor = vec4(base.rgb * (0.15 + 0.85 * diffuse), base.a);
}
)";

std::string defines(uint32_t f) {
    std::string s = "#version 450 core\n";
    if (f & kHasNormals) s += "#define HAS_NORMALS\n";
    if (f & kHasUv0) s += "#define HAS_UV0\n";
    if (f & kBaseColorMap) s += "#define BASE_COLOR_MAP\n";
    if (f & kNormalMap) s += "#define NORMAL_MAP\n";
    if (f & kAlphaMask) s += "#define ALPHA_MASK\n";
    return s;
}

GLuint compileStage(GLenum stage, const std::string& source) {
    GLuint shader = glCreateShader(stage);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw LoadFailure(std::string("peer shader does not compile: ") + log);
    }
    return shader;
}

} // namespace

PeerGl::~PeerGl() {
    for (auto& [features, p] : programs_)
        glDeleteProgram(p);
    if (!textures_.empty()) glDeleteTextures(GLsizei(textures_.size()), textures_.data());
    if (!vertexArrays_.empty())
        glDeleteVertexArrays(GLsizei(vertexArrays_.size()), vertexArrays_.data());
    if (!buffers_.empty()) glDeleteBuffers(GLsizei(buffers_.size()), buffers_.data());
}

GLuint PeerGl::buffer(uint64_t bytes, const void* data) {
    GLuint b = 0;
    glCreateBuffers(1, &b);
    glNamedBufferStorage(b, GLsizeiptr(std::max<uint64_t>(bytes, 1)), data,
                         data ? 0 : GL_DYNAMIC_STORAGE_BIT);
    buffers_.push_back(b);
    bufferBytes += bytes;
    return b;
}

GLuint PeerGl::vertexArray() {
    GLuint v = 0;
    glCreateVertexArrays(1, &v);
    vertexArrays_.push_back(v);
    return v;
}

GLuint PeerGl::textureRgba8(const uint8_t* pixels, int width, int height) {
    if (width <= 0 || height <= 0) throw LoadFailure("texture with no texels");
    int levels = 1;
    while ((std::max(width, height) >> levels) > 0)
        ++levels;
    GLuint t = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, levels, GL_RGBA8, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    textures_.push_back(t);
    ++textures;
    mipLevels += uint32_t(levels);
    // Level 0 plus the chain: about 4/3 of the base level.
    textureBytes += uint64_t(width) * uint64_t(height) * 4 * 4 / 3;
    return t;
}

void PeerGl::generateMipmaps() {
    for (GLuint t : textures_)
        glGenerateTextureMipmap(t);
    glFinish();
}

GLuint PeerGl::program(uint32_t features) {
    if (auto it = programs_.find(features); it != programs_.end()) return it->second;
    const std::string head = defines(features);
    GLuint vs = compileStage(GL_VERTEX_SHADER, head + kVertexSource);
    GLuint fs = 0;
    try {
        fs = compileStage(GL_FRAGMENT_SHADER, head + kFragmentSource);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetProgramInfoLog(p, sizeof log, nullptr, log);
        glDeleteProgram(p);
        throw LoadFailure(std::string("peer program does not link: ") + log);
    }
    programs_[features] = p;
    return p;
}

std::pair<double, double> PeerGl::mipsAndPrograms(const std::vector<uint32_t>& features) {
    auto phase = Clock::now();
    generateMipmaps();
    const double mipsMs = msSince(phase);
    phase = Clock::now();
    for (uint32_t f : features)
        program(f);
    glFinish();
    return {mipsMs, msSince(phase)};
}

} // namespace pnb::bench
