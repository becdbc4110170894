# pnb_add_scene(TARGET name SOURCE file OUTPUT file [OPTIONS args...] [DEPENDS files...] [ALL])
#
# Converts a scene with pnb-convert as a build step. pnb-convert writes a dependency file
# listing every file it read (buffers, MTL libraries, images, sidecar, camera path), so Ninja
# reconverts exactly when one of them changes, and converts independent scenes in parallel.
#
#   pnb_add_scene(TARGET city SOURCE ${CMAKE_CURRENT_SOURCE_DIR}/city.gltf
#                 OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/city.pnb OPTIONS --quantize)
#
# The converter is the target pnb::pnb-convert: in Penumbra's own build an ALIAS of pnb-convert
# (built first), in a project that did find_package(Penumbra) the installed, imported tool. The
# converter embeds its shaders, so nothing else is needed at conversion time.
function(pnb_add_scene)
    cmake_parse_arguments(S "ALL" "TARGET;SOURCE;OUTPUT" "OPTIONS;DEPENDS" ${ARGN})
    if(NOT S_TARGET OR NOT S_SOURCE OR NOT S_OUTPUT)
        message(FATAL_ERROR "pnb_add_scene needs TARGET, SOURCE and OUTPUT")
    endif()
    # (Inside Penumbra's own build the alias is defined later, with converter/.)
    if(NOT TARGET pnb::pnb-convert AND NOT PROJECT_NAME STREQUAL "Penumbra")
        message(FATAL_ERROR "pnb_add_scene: no target pnb::pnb-convert (find_package(Penumbra) "
            "provides it)")
    endif()
    set(depfile_args)
    if(CMAKE_GENERATOR MATCHES "Ninja|Makefiles")
        set(depfile_args DEPFILE ${S_OUTPUT}.d)
    endif()
    add_custom_command(OUTPUT ${S_OUTPUT}
        COMMAND pnb::pnb-convert ${S_SOURCE} -o ${S_OUTPUT} --depfile ${S_OUTPUT}.d --quiet
                ${S_OPTIONS}
        DEPENDS pnb::pnb-convert ${S_SOURCE} ${S_DEPENDS}
        ${depfile_args}
        COMMENT "Converting ${S_SOURCE}"
        VERBATIM)
    if(S_ALL)
        add_custom_target(${S_TARGET} ALL DEPENDS ${S_OUTPUT})
    else()
        add_custom_target(${S_TARGET} DEPENDS ${S_OUTPUT})
    endif()
endfunction()
