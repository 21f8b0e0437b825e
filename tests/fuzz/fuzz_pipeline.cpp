// libFuzzer target: the whole pipeline on small models. glTF bytes are loaded (as the page does); a
// model of at most 400 triangles and 8 normalized square units of surface is analysed with coarse
// samples (so one input takes milliseconds), resized by one step along its first principal offset
// when it has one, and written to .glb bytes, which must load again. Every stage returns a Status; none may crash, throw or trip a sanitizer.
// scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#define RESTITCH_GLTF_IMPLEMENTATION
#include "restitch/io/gltf.hpp"
#include "restitch/restitch.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  restitch::Result<restitch::Mesh> mesh = restitch::load_gltf_from_memory(data, size, "");
  if (!mesh.ok() || mesh->triangle_count() > 400 || mesh->vertex_count() > 1200) return 0;
  // The samples grow with the surface area, not the triangle count: 72 slivers spanning the whole box
  // took a second under ASan. At most 8 normalized square units (a 2 x 2 square, both sides).
  const double scale = 2.0 / restitch::bounding_box(*mesh).size().maxCoeff();
  double area = 0;
  for (Eigen::Index f = 0; f < mesh->F.rows(); ++f) area += 0.5 * restitch::double_area(*mesh, f);
  if (!(area * scale * scale <= 8)) return 0;
  restitch::AnalysisOptions<> options;
  options.dense_spacing = 0.08;
  options.feature_spacing = 0.2;
  options.vertex_cap = 100;
  options.find_short_periods = false;
  restitch::Result<restitch::Analysis> a = restitch::analyze(*mesh, options);
  if (!a.ok()) return 0;
  restitch::RetargetOptions ro;
  ro.max_problem_size = 20000;
  restitch::Retargeter<> r(*mesh, *a, ro);
  Eigen::Array3i steps = Eigen::Array3i::Zero();
  for (int axis = 0; axis < 3; ++axis)
    if (!a->lattice.dummy[std::size_t(axis)]) {
      steps[axis] = 1;
      break;
    }
  restitch::Result<restitch::RetargetResult> out = r.retarget(steps);
  if (!out.ok()) return 0;
  restitch::Result<std::vector<std::uint8_t>> glb = restitch::save_glb_to_memory(out->mesh);
  if (!glb.ok()) return 0;
  if (!restitch::load_gltf_from_memory(glb->data(), glb->size(), "").ok()) std::abort();  // a round trip
  return 0;
}
