// The deform pass (deform.h, shaders/deform.comp): one dispatch per deformed node, once per
// frame, before anything draws.
#include "anim/deform.h"

#include "load/upload.h"             // meshLayout (the stored streams' offsets, for a restore)
#include "shared/deform_params.h"    // bindings and uniform locations (GLSL and C++)

namespace pnb::player {

void runDeformPass(const GpuScene& scene, DeformContext& dc, GpuTimer& timer, FrameStats& stats) {
    const AnimationUpdate& up = dc.update;
    if (!scene.animation || (!up.deform && !up.restore)) return;
    const SceneAnimation& a = *scene.animation;
    timer.mark("deform");
    if (up.restore) {
        // The stored streams, as the loader first copied them (createPosedMesh).
        for (const DeformedNode& d : a.deformed) {
            const GpuMesh& src = scene.meshes[d.sourceMesh];
            const GpuMesh& posed = scene.meshes[d.posedMesh];
            const GLsizeiptr n = GLsizeiptr(d.vertexCount);
            glCopyNamedBufferSubData(src.buffer.id(), posed.buffer.id(), GLintptr(d.position) * 4, 0, n * 12);
            if (d.normal != PNB_DEFORM_ABSENT)
                glCopyNamedBufferSubData(src.buffer.id(), posed.buffer.id(), GLintptr(d.normal) * 4,
                                         GLintptr(d.posedNormal) * 4, n * 12);
            if (d.tangent != PNB_DEFORM_ABSENT)
                glCopyNamedBufferSubData(src.buffer.id(), posed.buffer.id(), GLintptr(d.tangent) * 4,
                                         GLintptr(d.posedTangent) * 4, n * 16);
        }
        timer.mark("setup");
        return;
    }
    if (!a.deformProgram || !scene.programs[*a.deformProgram]) return;
    const size_t bytes = std::max<size_t>(dc.state.frameData.size() * 4, 16);
    if (dc.frameBytes < bytes) {
        dc.frameBuffer = createBuffer();
        glNamedBufferStorage(dc.frameBuffer.id(), GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
        dc.frameBytes = bytes;
    }
    if (!dc.state.frameData.empty())
        glNamedBufferSubData(dc.frameBuffer.id(), 0, GLsizeiptr(dc.state.frameData.size() * 4), dc.state.frameData.data());
    const GLuint program = scene.programs[*a.deformProgram].id();
    glUseProgram(program);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_DEFORM_FRAME, dc.frameBuffer.id());
    for (const DeformedNode& d : a.deformed) {
        if (d.vertexCount == 0) continue;
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_DEFORM_SOURCE, scene.meshes[d.sourceMesh].buffer.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_DEFORM_POSED, scene.meshes[d.posedMesh].buffer.id());
        if (d.morphDeltas) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_DEFORM_MORPH, d.morphDeltas.id());
        glUniform1ui(PNB_DEFORM_LOC_VERTEX_COUNT, d.vertexCount);
        glUniform1ui(PNB_DEFORM_LOC_SOURCE_POSITION, d.position);
        glUniform1ui(PNB_DEFORM_LOC_SOURCE_NORMAL, d.normal);
        glUniform1ui(PNB_DEFORM_LOC_SOURCE_TANGENT, d.tangent);
        glUniform1ui(PNB_DEFORM_LOC_SOURCE_JOINTS, d.joints == PNB_DEFORM_ABSENT ? 0u : d.joints);
        glUniform1ui(PNB_DEFORM_LOC_JOINTS_U16, d.jointsU16 ? 1u : 0u);
        glUniform1ui(PNB_DEFORM_LOC_SOURCE_WEIGHTS, d.weights == PNB_DEFORM_ABSENT ? 0u : d.weights);
        glUniform1ui(PNB_DEFORM_LOC_JOINT_BASE, d.jointBase);
        glUniform1ui(PNB_DEFORM_LOC_JOINT_COUNT, d.jointCount);
        glUniform1ui(PNB_DEFORM_LOC_TARGET_COUNT, d.targetCount);
        glUniform1ui(PNB_DEFORM_LOC_WEIGHT_BASE, d.weightBase);
        glUniform1ui(PNB_DEFORM_LOC_MORPH_STRIDE, d.vertexCount * 3);
        glUniform1ui(PNB_DEFORM_LOC_MORPH_ATTRIBUTES, d.morphAttributes);
        glUniform1ui(PNB_DEFORM_LOC_POSED_NORMAL, d.posedNormal == PNB_DEFORM_ABSENT ? 0u : d.posedNormal);
        glUniform1ui(PNB_DEFORM_LOC_POSED_TANGENT, d.posedTangent == PNB_DEFORM_ABSENT ? 0u : d.posedTangent);
        glDispatchCompute((d.vertexCount + PNB_DEFORM_GROUP_SIZE - 1) / PNB_DEFORM_GROUP_SIZE, 1, 1);
        ++stats.deformDispatches;
        stats.deformVertices += d.vertexCount;
    }
    // Every later pass reads the posed streams as vertex attributes; captures and tests read
    // them back as buffers.
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
    timer.mark("setup");
}

} // namespace pnb::player
