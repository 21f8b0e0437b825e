# Emscripten must never see /usr/include (glibc headers break it), and
# find_package does not see Debian's packages under emcmake. So the
# Emscripten configuration gets a build-local folder of symbolic links to
# exactly the header-only dependencies, added with -isystem (docs/building.md).
if(EMSCRIPTEN)
  set(RESTITCH_WASM_SYSROOT "${CMAKE_BINARY_DIR}/wasm-deps")
  file(MAKE_DIRECTORY "${RESTITCH_WASM_SYSROOT}")
  foreach(link IN ITEMS
      "Eigen=/usr/include/eigen3/Eigen"
      "unsupported=/usr/include/eigen3/unsupported"
      "nanoflann.hpp=/usr/include/nanoflann.hpp"
      "tiny_gltf.h=/usr/include/tiny_gltf.h"
      "nlohmann=/usr/include/nlohmann"
      "catch2=/usr/include/catch2"
      "CLI=/usr/include/CLI")
    string(REPLACE "=" ";" parts "${link}")
    list(GET parts 0 name)
    list(GET parts 1 target)
    if(NOT EXISTS "${target}")
      message(FATAL_ERROR "restitch (wasm): ${target} is missing; install the Debian package that provides it (scripts/install-deps.sh)")
    endif()
    if(NOT EXISTS "${RESTITCH_WASM_SYSROOT}/${name}")
      file(CREATE_LINK "${target}" "${RESTITCH_WASM_SYSROOT}/${name}" SYMBOLIC)
    endif()
  endforeach()
  add_library(restitch_wasm_sysroot INTERFACE)
  target_compile_options(restitch_wasm_sysroot INTERFACE "SHELL:-isystem ${RESTITCH_WASM_SYSROOT}")
endif()

# Declares an imported header-only target that points at the link folder.
function(restitch_wasm_header_target name)
  if(NOT TARGET ${name})
    add_library(${name} INTERFACE IMPORTED GLOBAL)
    target_link_libraries(${name} INTERFACE restitch_wasm_sysroot)
  endif()
endfunction()
