// Uses the installed headers: builds a sample, writes it as glTF, reads it back.
#define RESTITCH_GLTF_IMPLEMENTATION
#include <restitch/families/families.hpp>
#include <restitch/io/gltf.hpp>
#include <restitch/restitch.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  auto sample = restitch::families::generate("pin_header");
  if (!sample) return std::fprintf(stderr, "%s\n", sample.status().message().c_str()), 1;
  if (auto s = restitch::save_gltf(sample->mesh, argv[1]); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
  auto back = restitch::load_gltf(argv[1]);
  if (!back || back->triangle_count() != sample->mesh.triangle_count()) return std::fprintf(stderr, "round trip failed\n"), 1;
  std::printf("consumer ok: %zu triangles\n", back->triangle_count());
  return 0;
}
