# nanoflann (Debian: libnanoflann-dev, header /usr/include/nanoflann.hpp) -> nanoflann::nanoflann
if(EMSCRIPTEN)
  restitch_wasm_header_target(nanoflann::nanoflann)
else()
  find_package(nanoflann REQUIRED CONFIG)
endif()
