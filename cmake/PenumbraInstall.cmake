# Install and export rules, the CMake package (find_package(Penumbra)) and the CPack Debian
# package. Included last from the top-level CMakeLists.txt, once every target exists.
#
#   cmake --install build/release --prefix /opt/penumbra    # then, in a user's project:
#   find_package(Penumbra REQUIRED)  # pnb::format, pnb::player, pnb::pnb-convert, pnb_add_scene()
#   cd build/release && cpack -G DEB                          # penumbra_<version>_<arch>.deb
#
# The libraries are static, so their private link items (zstd, xxhash, GLFW, zlib, ...) are part
# of the exported link interface and PenumbraConfig.cmake finds them again (find_dependency);
# pnb_warnings is linked as $<BUILD_INTERFACE:...> and stays out of the export.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PNB_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Penumbra)
set(PNB_INSTALL_DOCDIR ${CMAKE_INSTALL_DATAROOTDIR}/doc/penumbra)
set(PNB_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/penumbra)

# The user tools (not tests, benchmarks or fuzzers), imported as pnb::pnb-convert etc.
set(PNB_TOOLS pnb-convert pnb-play pnb-judge pnb-edit pnb-inspect pnb-reference pnb-flip pnb-make-scene
    pnb-make-sample)

# Exported names: pnb_format -> pnb::format, ... (the same ALIAS names exist in the build).
set_target_properties(pnb_format PROPERTIES EXPORT_NAME format)
set_target_properties(pnb_player PROPERTIES EXPORT_NAME player)
set_target_properties(pnb_player_math PROPERTIES EXPORT_NAME player_math)
set_target_properties(pnb_lighting PROPERTIES EXPORT_NAME lighting)
set_target_properties(pnb_image_write PROPERTIES EXPORT_NAME image_write)
set_target_properties(pnb_path_json PROPERTIES EXPORT_NAME path_json)
set_target_properties(pnb_play_harness PROPERTIES EXPORT_NAME play_harness)

# A sanitized build installs sanitized libraries: whoever links them needs the sanitizer
# runtime, so the installed interface carries the flag (the build tree has add_link_options).
if(PNB_SANITIZE)
    target_link_options(pnb_format INTERFACE $<INSTALL_INTERFACE:-fsanitize=${PNB_SANITIZE}>)
endif()

# Component "format": pnb::format and the tools. Component "player": the renderer library.
install(TARGETS ${PNB_TOOLS} EXPORT PenumbraTargets RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS pnb_format EXPORT PenumbraTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS pnb_player pnb_player_math pnb_lighting pnb_image_write pnb_path_json pnb_play_harness
    EXPORT PenumbraPlayerTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT PenumbraTargets NAMESPACE pnb:: DESTINATION ${PNB_INSTALL_CMAKEDIR})
install(EXPORT PenumbraPlayerTargets NAMESPACE pnb:: DESTINATION ${PNB_INSTALL_CMAKEDIR})

# Public headers (player/math/ is internal to the renderer).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/format/include/pnb
                  ${PROJECT_SOURCE_DIR}/player/include/pnb_player
                  ${PROJECT_SOURCE_DIR}/player/harness/include/pnb_player
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/PenumbraConfig.cmake.in
    ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake INSTALL_DESTINATION ${PNB_INSTALL_CMAKEDIR})
# 0.x: a minor version may break the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake
              ${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/PnbAddScene.cmake
    DESTINATION ${PNB_INSTALL_CMAKEDIR})

# Documentation, and the benchmark plot script for --compare plots by hand (pnb-play itself runs
# its embedded copy).
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${PNB_INSTALL_DOCDIR})
file(GLOB pnb_docs CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${pnb_docs} DESTINATION ${PNB_INSTALL_DOCDIR}/docs)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/player/tools/plot_frames.py
    DESTINATION ${PNB_INSTALL_DATADIR})

# pnb-sweep: the Python runner in share/penumbra/sweep, and bin/pnb-sweep that runs it with the
# tools beside it (python3 >= 3.11; the report needs python3-matplotlib).
install(PROGRAMS ${PROJECT_SOURCE_DIR}/sweep/pnb_sweep.py DESTINATION ${PNB_INSTALL_DATADIR}/sweep)
install(FILES ${PROJECT_SOURCE_DIR}/sweep/sweep_report.py ${PROJECT_SOURCE_DIR}/sweep/slurm_cluster.py
    ${PROJECT_SOURCE_DIR}/sweep/sweep_command.py ${PROJECT_SOURCE_DIR}/sweep/output_guard.py
    ${PROJECT_SOURCE_DIR}/sweep/sweep_schema.py ${PROJECT_SOURCE_DIR}/sweep/budget_search.py
    ${PROJECT_SOURCE_DIR}/sweep/budget_command.py
    DESTINATION ${PNB_INSTALL_DATADIR}/sweep)
file(RELATIVE_PATH PNB_BIN_TO_DATA /${CMAKE_INSTALL_BINDIR} /${PNB_INSTALL_DATADIR})
configure_file(${PROJECT_SOURCE_DIR}/cmake/pnb-sweep.in ${PROJECT_BINARY_DIR}/pnb-sweep @ONLY)
install(PROGRAMS ${PROJECT_BINARY_DIR}/pnb-sweep DESTINATION ${CMAKE_INSTALL_BINDIR})

# --- CPack: the Debian package "penumbra".
# Depends = the shared libraries the tools load (dpkg-shlibdeps, from dpkg-dev) + the -dev
# packages PenumbraConfig.cmake's find_dependency() calls need + libEGL, each looked up with
# dpkg-query from a file the build itself found (so the list follows what the build uses).
set(pnb_dev_files ${PKG_CONFIG_EXECUTABLE})
foreach(module libzstd libxxhash epoxy glfw3)
    pkg_get_variable(pcdir ${module} pcfiledir)
    list(APPEND pnb_dev_files ${pcdir}/${module}.pc)
endforeach()
list(APPEND pnb_dev_files ${glm_DIR}/glmConfig.cmake
    ${nlohmann_json_DIR}/nlohmann_jsonConfig.cmake ${ZLIB_INCLUDE_DIR}/zlib.h)
# libepoxy loads libEGL at run time (dlopen: pnb-play --headless, the editor), which
# dpkg-shlibdeps cannot see: the package that owns the library the build found.
find_library(PNB_EGL_LIBRARY EGL)
if(PNB_EGL_LIBRARY)
    file(REAL_PATH ${PNB_EGL_LIBRARY} egl_library)
    list(APPEND pnb_dev_files ${egl_library})
endif()
# One dpkg-query for all files (about a second), redone only when the files change.
if(NOT "${pnb_dev_files}" STREQUAL "${PNB_DEB_DEPENDS_FILES}")
    find_program(PNB_DPKG_QUERY dpkg-query)
    set(packages)
    if(PNB_DPKG_QUERY)
        # "libzstd-dev:amd64: /usr/lib/.../libzstd.pc" per file ("a, b: path" when shared)
        execute_process(COMMAND ${PNB_DPKG_QUERY} -S ${pnb_dev_files} OUTPUT_VARIABLE out
            ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
        string(REPLACE "\n" ";" lines "${out}")
        foreach(file IN LISTS pnb_dev_files)
            set(package)
            foreach(line IN LISTS lines)
                if(line MATCHES "^([a-z0-9][a-z0-9.+-]*)[^ ]*: (.*)$"
                   AND CMAKE_MATCH_2 STREQUAL file)
                    set(package ${CMAKE_MATCH_1})
                endif()
            endforeach()
            if(package)
                list(APPEND packages ${package})
            else()
                message(STATUS "penumbra .deb: no Debian package owns ${file}; not in Depends")
            endif()
        endforeach()
    endif()
    list(REMOVE_DUPLICATES packages)
    list(JOIN packages ", " packages)
    set(PNB_DEB_DEPENDS "${packages}" CACHE INTERNAL "the .deb's Depends besides shlibdeps")
    set(PNB_DEB_DEPENDS_FILES "${pnb_dev_files}" CACHE INTERNAL "files PNB_DEB_DEPENDS is from")
endif()

set(CPACK_PACKAGE_NAME penumbra)
set(CPACK_PACKAGE_VENDOR "Penumbra")
set(CPACK_PACKAGE_CONTACT "Penumbra developers <penumbra@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Asset pipeline (pnb-convert), .pnb container library, OpenGL player and material editor")
set(CPACK_PACKAGE_INSTALL_DIRECTORY penumbra)
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# python3 >= 3.11 (tomllib) and python3-jsonschema (its file schemas): pnb-sweep.
if(PNB_DEB_DEPENDS)
    set(CPACK_DEBIAN_PACKAGE_DEPENDS "${PNB_DEB_DEPENDS}, python3 (>= 3.11), python3-jsonschema")
else()
    set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= 3.11), python3-jsonschema")
endif()
# Mesa's drivers (llvmpipe when there is no GPU); pnb-play's benchmark plots and pnb-sweep's
# report (optional: pnb-play warns and goes on without them); pnb-sweep run --slurm's clients.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libgl1-mesa-dri")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-matplotlib, slurm-client")
include(CPack)
