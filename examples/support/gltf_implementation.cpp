// The one translation unit that compiles tinygltf's implementation for
// restitch's own programs (CLI, tests, bench, wasm module).
#define RESTITCH_GLTF_IMPLEMENTATION
#include "restitch/io/gltf.hpp"
