// libFuzzer target: glTF bytes (.glb or .gltf JSON) to a Mesh, through the entry the web page uses
// (load_gltf_from_memory, no external files). Any input must give a Mesh or a Status, never a crash,
// a sanitizer report or an exception; a Mesh that loads passes restitch::validate. scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#define RESTITCH_GLTF_IMPLEMENTATION
#include "restitch/io/gltf.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  restitch::GltfLoadReport report;
  restitch::Result<restitch::Mesh> m = restitch::load_gltf_from_memory(data, size, "", &report);
  if (m.ok() && !restitch::validate(*m).ok()) std::abort();  // the loader promises a valid mesh
  return 0;
}
