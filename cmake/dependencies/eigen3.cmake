# Eigen 3.4 (Debian: libeigen3-dev) -> Eigen3::Eigen
if(EMSCRIPTEN)
  restitch_wasm_header_target(Eigen3::Eigen)
else()
  find_package(Eigen3 3.3 REQUIRED CONFIG)
endif()
