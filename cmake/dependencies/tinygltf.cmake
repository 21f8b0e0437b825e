# tinygltf 2.7 (Debian: libtinygltf-dev) with nlohmann-json (nlohmann-json3-dev) -> restitch_tinygltf
# Only the header is used (Debian's libtinygltf.so is never linked: the wasm
# build cannot); restitch compiles the implementation in one translation unit
# (RESTITCH_GLTF_IMPLEMENTATION). Images are passed through undecoded, so
# stb is not needed.
if(EMSCRIPTEN)
  restitch_wasm_header_target(restitch_tinygltf)
else()
  find_package(nlohmann_json 3 REQUIRED CONFIG)
  find_path(TINYGLTF_INCLUDE_DIR tiny_gltf.h REQUIRED)
  add_library(restitch_tinygltf INTERFACE IMPORTED)
  target_link_libraries(restitch_tinygltf INTERFACE nlohmann_json::nlohmann_json)
  if(NOT TINYGLTF_INCLUDE_DIR STREQUAL "/usr/include")
    target_include_directories(restitch_tinygltf SYSTEM INTERFACE "${TINYGLTF_INCLUDE_DIR}")
  endif()
endif()
