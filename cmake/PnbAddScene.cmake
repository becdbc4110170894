# pnb_add_scene(TARGET name SOURCE file OUTPUT file [OPTIONS args...] [DEPENDS files...] [ALL])
#
# Converts a scene with pnb-convert as a build step. pnb-convert writes a dependency file
# listing every file it read (buffers, MTL libraries, images, sidecar, camera path), so Ninja
# reconverts exactly when one of them changes, and converts independent scenes in parallel.
#
#   pnb_add_scene(TARGET city SOURCE ${CMAKE_CURRENT_SOURCE_DIR}/city.gltf
#                 OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/city.pnb OPTIONS --quantize)
function(pnb_add_scene)
    cmake_parse_arguments(S "ALL" "TARGET;SOURCE;OUTPUT" "OPTIONS;DEPENDS" ${ARGN})
    if(NOT S_TARGET OR NOT S_SOURCE OR NOT S_OUTPUT)
        message(FATAL_ERROR "pnb_add_scene needs TARGET, SOURCE and OUTPUT")
    endif()
    set(depfile_args)
    if(CMAKE_GENERATOR MATCHES "Ninja|Makefiles")
        set(depfile_args DEPFILE ${S_OUTPUT}.d)
    endif()
    add_custom_command(OUTPUT ${S_OUTPUT}
        COMMAND pnb-convert ${S_SOURCE} -o ${S_OUTPUT} --depfile ${S_OUTPUT}.d --quiet ${S_OPTIONS}
        DEPENDS pnb-convert ${S_SOURCE} ${S_DEPENDS}
        ${depfile_args}
        COMMENT "Converting ${S_SOURCE}"
        VERBATIM)
    if(S_ALL)
        add_custom_target(${S_TARGET} ALL DEPENDS ${S_OUTPUT})
    else()
        add_custom_target(${S_TARGET} DEPENDS ${S_OUTPUT})
    endif()
endfunction()
