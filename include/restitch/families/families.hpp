// restitch/families/families.hpp - parametric man-made sample models with exactly known repeats.
//
// The embedded default models of the CLI and the web demo, and the ground
// truth of the tests: every sample is a `Mesh` (normals, one UV set, 2-4
// materials, one group per material) together with its true lattice
// generators.
//
//   bookshelf       columns x shelves compartments, side panels, top and
//                   bottom boards, dividers, shelf boards, a back panel.   m
//   facade          a wall with columns x floors windows (frame, glass,
//                   sill), a plinth and a parapet with a cornice.          m
//   facade_sheared  the same with every floor shifted sideways by `shear`:
//                   generators (bay_width, 0, 0) and (shear, floor_height, 0).
//   fence           pickets with pointed tops on two rails between posts.   m
//   pin_header      pins at 2.54 mm in a body of one segment per pin.       mm
//
// and, with structure around the repeat (restitch/families/structured.hpp;
// SampleModel::parts lists what occurs once):
//
//   box_header      a shrouded two-row header, a key notch centred.         mm
//   cabinet         short drawers over one tall drawer.                     m
//   connector       a housing reaching past pin 1 (at the origin), a key,
//                   a back-wall slot next to each end; `one_piece`: the
//                   housing's faces whole over its length (as CAD).        mm
//   dip             a dual in-line package: two rows of pins under one
//                   body, a pin-1 dimple reaching into the gap after pin 1. mm
//   radiator        sections, a valve under one of them; `drift` grows the
//                   pitch along the row (no exact copies).                  m
//   railing         balusters alternating plain / with a ring: the period
//                   is the pair.                                            m
//   shutter         slats in two runs split by a middle rail.               m
//   tube_rail       a closed round rail through posts; `jitter`, `twist`
//                   make its copies differ slightly (no exact copies).      m
//
// Coordinates: y up, x along the first generator, z towards the viewer
// (front faces at the largest z), model units as listed (m or mm).
//
// THE KEY PROPERTY (of the plain families; the structured ones keep it for
// the modules no part changes). Along every generator g a sample is
//   [start cap] [module] x modules[g] [end cap]
// where the modules are exact translates of one template module: block b of
// generator g sits at `origin + b * generators[g]` (plus the other
// generator's offset), computed as i * pitch, never by accumulation. Parts
// that run the whole length (a back panel, rails, the pin header's body) are
// cut at module boundaries, and faces hidden by contact at a module boundary
// are left out, so every module is the same set of triangles translated, and
// the surface is the surface of the real object. Hence
// `generate(name, {count = n + k})` is exactly the model with k more modules
// along g: what a perfect resize by k steps along g must produce (the start
// cap stays, the modules and the end cap beyond move by k * generators[g]).
// Positions are float, so "exactly" means to float rounding of the model
// coordinates (about 1e-7 relative); normals and UVs of corresponding faces
// are bit-identical.
//
// Contract:
//  * `catalog()` lists every sample in a fixed (alphabetical) order with its
//    parameters, defaults and allowed ranges; counts and `detail` are
//    integers >= 1.
//  * `generate(name, overrides)` returns invalid_argument, with a message
//    listing what is allowed, for an unknown sample or parameter, a value
//    outside its range or a non-integer count, and for combinations that do
//    not fit (a window wider than its bay...); too_large when the mesh would
//    exceed `max_sample_triangles`. It never throws.
//  * Defaults: 1k-5k triangles, at least 3 repeats along every generator,
//    each generator longer than 0.15 in normalized units (2 / longest side).
//  * `detail` refines the tessellation: every edge is cut into pieces no
//    longer than cell / detail (cell: 0.1 m bookshelf, 1 m facade, 0.1 m
//    fence, 1 mm pin header), so the triangle count grows about as
//    detail^2. About 200k triangles with the other defaults: bookshelf
//    detail 8 (184k), facade 12 (188k), fence 16 (174k), pin_header 16 (229k).
//  * UVs: a box mapping of block-local coordinates (one texture repeat per
//    metre, per 10 mm for the pin header), identical in every module.
//  * Deterministic: the same parameters give the same mesh bit for bit.
//
// Cost: O(#F) time and memory; a counting pass (O(#patches)) runs first so a
// too-large request allocates nothing.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

#include "restitch/families/generators.hpp"
#include "restitch/families/model.hpp"

namespace restitch {
namespace families {

/// Every sample, in a fixed (alphabetical) order, with its parameters and defaults.
template <class = void>
const std::vector<SampleInfo>& catalog() {
  static const std::vector<SampleInfo> c = [] {
    std::vector<SampleInfo> v;
    for (const auto& f : detail::families()) v.push_back(f.info());
    return v;
  }();
  return c;
}

/// The sample `name` with its defaults changed by `overrides` (parameter
/// name -> value). See the contract at the top of this file. Cost O(#F).
template <class = void>
Result<SampleModel> generate(const std::string& name, const std::map<std::string, double>& overrides = {}) {
  return restitch::detail::guarded("generate", [&]() -> Result<SampleModel> {
    const auto& fams = detail::families();
    const auto& cat = catalog();
    std::size_t k = 0;
    while (k < cat.size() && cat[k].name != name) ++k;
    if (k == cat.size()) {
      std::string names;
      for (const auto& s : cat) names += (names.empty() ? "" : ", ") + s.name;
      return error(StatusCode::invalid_argument, "unknown sample '" + name + "'; the samples are: " + names);
    }
    const SampleInfo& info = cat[k];
    std::map<std::string, double> values;
    for (const auto& p : info.parameters) values[p.name] = p.value;
    for (const auto& [key, v] : overrides) {
      const Parameter* p = nullptr;
      for (const auto& q : info.parameters)
        if (q.name == key) p = &q;
      if (!p) {
        std::string names;
        for (const auto& q : info.parameters) names += (names.empty() ? "" : ", ") + q.name;
        return error(StatusCode::invalid_argument,
                     "sample '" + name + "' has no parameter '" + key + "'; its parameters are: " + names);
      }
      const std::string range = "[" + detail::format_number(p->min) + ", " + detail::format_number(p->max) + "]";
      if (!(v >= p->min && v <= p->max))
        return error(StatusCode::invalid_argument, "parameter '" + key + "' of sample '" + name + "' is " +
                                                       detail::format_number(v) + ", outside its range " + range);
      if (p->integer && v != std::floor(v))
        return error(StatusCode::invalid_argument, "parameter '" + key + "' of sample '" + name +
                                                       "' must be an integer in " + range + ", got " +
                                                       detail::format_number(v));
      values[key] = v;
    }
    const detail::ParameterValues P(std::move(values));
    const detail::SampleFamily& fam = fams[k];
    RESTITCH_TRY(fam.check(P));
    const double cell = fam.cell / P["detail"];
    {
      SampleModel scratch;
      restitch::detail::SampleMeshBuilder counter(cell, fam.uv_unit, 2, true);
      fam.build(P, counter, scratch);
      if (counter.triangle_count() > max_sample_triangles)
        return error(StatusCode::too_large, "sample '" + name + "' with these parameters would have " +
                                                std::to_string(counter.triangle_count()) + " triangles, more than " +
                                                std::to_string(max_sample_triangles) +
                                                "; lower `detail` or the counts");
    }
    SampleModel model;
    restitch::detail::SampleMeshBuilder builder(cell, fam.uv_unit, 2, false);
    fam.build(P, builder, model);
    Eigen::Index generators = static_cast<Eigen::Index>(model.generators.size());
    std::vector<Eigen::VectorXi> blocks;
    builder.finish(name, model.mesh, blocks);
    blocks.resize(std::size_t(generators));
    model.face_block = std::move(blocks);
    return model;
  });
}

}  // namespace families
}  // namespace restitch
