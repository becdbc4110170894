// bindings.h — the binding point of every uniform block and storage buffer, named once for the
// shaders' `layout(binding = ...)` and the player's glBindBufferRange/Base calls. Plain #defines:
// GLSL and C++ read them alike (gpu_layout.h, which says how the block headers serve both
// languages, needs nothing here). Texture units keep their numbers where they are declared
// (interface.glsl's PNB_TEX_*, the samplers' own layout lines).
//
// Uniform blocks and storage buffers are separate binding spaces in GL: the same number under
// both is no clash. Within one space, numbers may repeat only between programs that never run
// with the other's buffer bound (each group below says which).
#ifndef PNB_SHARED_BINDINGS_H
#define PNB_SHARED_BINDINGS_H

// Uniform blocks of the surface shaders (shaders/, packed into containers by the converter):
// changing a number breaks existing containers' shaders, so bump the PROG chunk version if you
// do (interface.glsl). The player's own programs that read these blocks use the same points.
#define PNB_BINDING_FRAME_BLOCK 0    /* shared/frame_block.h */
#define PNB_BINDING_OBJECT_BLOCK 1   /* shared/object_block.h */
#define PNB_BINDING_MATERIAL_BLOCK 2 /* shared/material_block.h */
#define PNB_BINDING_SHADOW_BLOCK 4   /* shared/shadow_block.h */
#define PNB_BINDING_GI_BLOCK 6       /* shared/gi_block.h */
#define PNB_BINDING_IBL_BLOCK 7      /* shared/ibl_block.h */

// Storage buffers of the surface shaders (the same contract as above).
#define PNB_BINDING_LIGHT_LIST 3     /* LightBuffer: shared/light_list.h, lights.glsl */
#define PNB_BINDING_CASTER_MASKS 5   /* CasterMasks: shadow.vert reads, sdsm.comp writes */
#define PNB_BINDING_LIGHT_CLUSTERS 8 /* LightClusters: shared/light_list.h, lights.glsl */
#define PNB_BINDING_LOCAL_SHADOWS 9  /* LocalShadows: local_shadows.glsl */
#define PNB_BINDING_INSTANCES 10     /* InstanceBlock: shared/instance_data.h, surface.vert */

// Storage buffers of the player's compute passes (player/shaders, embedded in the player: free
// to change with it). Each pass binds its own before it dispatches; the low numbers they reuse
// are rebound by whichever pass comes next.
// SDSM (sdsm.comp); its cull also writes the shadow pass's PNB_BINDING_CASTER_MASKS.
#define PNB_BINDING_SDSM_STATE 0      /* SdsmState: shared/sdsm_state.h (shadow_debug.frag too) */
#define PNB_BINDING_SDSM_SHADOW_OUT 1 /* ShadowOut: the ShadowBlock lighting then reads */
#define PNB_BINDING_SDSM_SHADOW_IN 2  /* ShadowIn: the CPU's ShadowBlock (parameters) */
#define PNB_BINDING_SDSM_COMMANDS 4   /* Commands: the shadow pass's indirect draws */
#define PNB_BINDING_SDSM_CASTERS 6    /* CasterBounds: shared/sdsm_caster.h */
// Light clusters (light_clusters.comp): it reads spheres and writes the masks lighting then reads
// at PNB_BINDING_LIGHT_CLUSTERS.
#define PNB_BINDING_CLUSTER_SPHERES 0    /* LightSpheres */
#define PNB_BINDING_CLUSTER_MASKS_OUT 1  /* LightClusters, written */
// GI: light propagation volumes (lpv_inject.comp, lpv_resolve.comp), virtual point lights
// (gi_vpls.comp, gi_probe_gather.comp).
#define PNB_BINDING_LPV_LIGHT 0    /* LightAccumulation */
#define PNB_BINDING_LPV_GEOMETRY 1 /* GeometryAccumulation */
#define PNB_BINDING_GI_VPLS 0      /* Vpls */
#define PNB_BINDING_GI_PROBE_NEEDED 1 /* ProbeNeeded */

#endif
