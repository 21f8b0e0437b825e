# Catch2 v2 (Debian: catch2) -> Catch2::Catch2, plus include(Catch) natively
if(EMSCRIPTEN)
  restitch_wasm_header_target(Catch2::Catch2)
else()
  find_package(Catch2 2 REQUIRED CONFIG)
  include(Catch)
endif()
