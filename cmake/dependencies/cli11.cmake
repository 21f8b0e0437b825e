# CLI11 (Debian: libcli11-dev) -> CLI11::CLI11
if(EMSCRIPTEN)
  restitch_wasm_header_target(CLI11::CLI11)
else()
  find_package(CLI11 CONFIG REQUIRED)
endif()
