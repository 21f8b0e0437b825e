// A program outside restitch: builds a sample, writes it as glTF and reads it back, finds how it
// repeats and resizes it by one repeat. Prints "consumer ok: ..." when every step did what it should.
#define RESTITCH_GLTF_IMPLEMENTATION
#include <restitch/families/families.hpp>
#include <restitch/io/gltf.hpp>
#include <restitch/restitch.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  auto sample = restitch::families::generate("pin_header", {{"pins", 4}});
  if (!sample) return std::fprintf(stderr, "%s\n", sample.status().message().c_str()), 1;
  if (auto s = restitch::save_gltf(sample->mesh, argv[1]); !s) return std::fprintf(stderr, "%s\n", s.message().c_str()), 1;
  auto mesh = restitch::load_gltf(argv[1]);
  if (!mesh || mesh->triangle_count() != sample->mesh.triangle_count())
    return std::fprintf(stderr, "round trip failed\n"), 1;
  auto analysis = restitch::analyze(*mesh);
  if (!analysis || analysis->principal.size() != 1) return std::fprintf(stderr, "no repeat found\n"), 1;
  restitch::Retargeter<> retargeter(*mesh, *analysis);
  auto longer = retargeter.retarget({1, 0, 0});
  if (!longer) return std::fprintf(stderr, "%s\n", longer.status().message().c_str()), 1;
  auto five = restitch::families::generate("pin_header", {{"pins", 5}});
  if (!five) return 1;
  const restitch::BoundingBox got = restitch::bounding_box(longer->mesh), want = restitch::bounding_box(five->mesh);
  if ((got.min - want.min).norm() > 1e-4 || (got.max - want.max).norm() > 1e-4)
    return std::fprintf(stderr, "the resize is not the 5-pin header in place\n"), 1;
  std::printf("consumer ok: %zu triangles, grown to %zu\n", mesh->triangle_count(), longer->mesh.triangle_count());
  return 0;
}
