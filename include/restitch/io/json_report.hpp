// restitch/io/json_report.hpp - analysis and retarget reports as JSON.
//
// The one definition of the fields `restitch analyze --json` and
// `restitch resize --json` print and the web demo exposes, so all three agree.
// Lengths are in model units.
//
// analysis_json: scale (normalized units per model unit), features,
//   dominant_offsets [{offset [x,y,z], votes, overlap, significant, divisor,
//   promoted, tests [{name, value, threshold, at_most, passed}], rejected_by}]
//   (divisor k >= 2: the peak was k periods long and offset is the period;
//   tests in the order they ran, see offsets/detector.hpp: votes is a count,
//   double_drift is in dense sample spacings, the others are shares of the
//   dense surface or their ratios, unitless; rejected_by names the failed
//   test, null when none failed; promoted: made principal on request),
//   candidates [{offset [x,y,z], copies, reason ("pair" | "parallel" | "vertices"),
//   dominant (index in dominant_offsets)}] (docs/method.md 1.10),
//   principal_offsets [[x,y,z]...] in order, dummy_directions [[x,y,z]...],
//   lattice_axes [[x,y,z] x3] (the principal offsets in order, then the dummy
//   directions), resizable [bool x3] (per lattice axis: false for a dummy),
//   lattice_cells [U,V,W], lattice_origin [x,y,z], sparsity {top7, top20, bins},
//   descriptor, matcher, detector (the offset detector's name), timings_ms {stage: ms}.
// retarget_json: steps, grid_steps, nodes, labels, edges, cycles, energy,
//   non_metric, cells_in, cells_out, size_in, size_out, timings_ms,
//   output {vertices, triangles}, checked (the result check ran, RetargetOptions::check),
//   boundary_edges {in, out, new} (open edges with positions welded, restitch/mesh_boundary.hpp; new:
//   those no copy of the input's own, restitch/retarget/check.hpp; null unless checked), weld_tolerance {relative (of the input's
//   diagonal, as the stitcher used it), measured (from the copies' vertices,
//   RetargetOptions::measure_weld_tolerance)}, pivot {modes, point, translation, low_end_cells},
//   exact {applied, scale, size_nearest}, seam_energy ("geometry" | "descriptor"),
//   sample_spacing, seam_tolerance, max_seam_mismatch (model units), seams [{cells [[i,j,k] x2]
//   (output cells; the second lies outside for an anchored end), labels [[du,dv,dw] x2], mismatch
//   (model units), outer, offset (cells from the cell face, docs/method.md 2.9)}] (docs/method.md 2.8),
//   warnings [{check, message}] (restitch/retarget/report.hpp, ResultWarning; empty when the result
//   passed every check), seams_moved,
//   plane_offsets [[..] x3] (per lattice axis, the offset of each plane between output cells; [] when
//   none moved, 2.9), parts [{axis (1-based lattice axis), cells [first, last] (1-based input cells),
//   anchor ("low end" | "high end" | "centre"), shift (cells it moved along its axis), half (+1 or -1: a
//   centred part moved alone a further half period that way, 0 otherwise)}] (parts that occur once, kept
//   once; docs/method.md 2.10).
#pragma once

#include <nlohmann/json.hpp>

#include "restitch/analysis.hpp"
#include "restitch/retarget.hpp"

namespace restitch {

namespace detail {
inline nlohmann::json vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
inline nlohmann::json arr3(const Eigen::Array3i& v) { return {v[0], v[1], v[2]}; }
template <class = void>
nlohmann::json tests_json(const DominantOffset& d) {
  nlohmann::json out = nlohmann::json::array();
  for (const OffsetTest& t : d.tests)
    out.push_back(
        {{"name", t.name}, {"value", t.value}, {"threshold", t.threshold}, {"at_most", t.at_most}, {"passed", t.passed}});
  return out;
}
}  // namespace detail

template <class = void>
nlohmann::json analysis_json(const Analysis& a) {
  nlohmann::json j;
  j["scale"] = a.normalization.scale;
  j["features"] = a.features.points.rows();
  j["dominant_offsets"] = nlohmann::json::array();
  for (const DominantOffset& d : a.dominant)
    j["dominant_offsets"].push_back({{"offset", detail::vec3(a.normalization.to_model_offset(d.offset))},
                                     {"votes", d.votes},
                                     {"overlap", d.overlap},
                                     {"significant", d.significant},
                                     {"divisor", d.divisor},
                                     {"promoted", d.promoted},
                                     {"tests", detail::tests_json(d)},
                                     {"rejected_by", d.failed_test() ? nlohmann::json(d.failed_test()->name)
                                                                     : nlohmann::json(nullptr)}});
  j["candidates"] = nlohmann::json::array();
  for (const RepeatCandidate& c : a.candidates)
    j["candidates"].push_back({{"offset", detail::vec3(a.model_units(c))},
                               {"copies", c.copies},
                               {"reason", c.reason},
                               {"dominant", c.dominant}});
  j["principal_offsets"] = nlohmann::json::array();
  for (const Eigen::Vector3d& v : a.principal_model_units()) j["principal_offsets"].push_back(detail::vec3(v));
  j["dummy_directions"] = nlohmann::json::array();
  for (int c = 0; c < 3; ++c)
    if (a.lattice.dummy[c]) j["dummy_directions"].push_back(detail::vec3(a.lattice.A.col(c)));
  j["lattice_axes"] = nlohmann::json::array();
  for (int c = 0; c < 3; ++c) j["lattice_axes"].push_back(detail::vec3(a.lattice.A.col(c)));
  j["resizable"] = nlohmann::json::array();
  for (int c = 0; c < 3; ++c) j["resizable"].push_back(!a.lattice.dummy[c]);
  j["lattice_cells"] = detail::arr3(a.lattice.cells);
  j["lattice_origin"] = detail::vec3(a.lattice.origin);
  j["sparsity"] = {{"top7", a.sparsity.top7}, {"top20", a.sparsity.top20}, {"bins", a.sparsity.bins}};
  j["descriptor"] = a.descriptor_name;
  j["matcher"] = a.matcher_name;
  j["detector"] = a.detector_name;
  j["timings_ms"] = a.timings_ms;
  return j;
}

template <class = void>
nlohmann::json retarget_json(const RetargetReport& r) {
  nlohmann::json j;
  j["steps"] = detail::arr3(r.steps);
  j["grid_steps"] = detail::arr3(r.grid_steps);
  j["nodes"] = r.nodes;
  j["labels"] = r.labels;
  j["edges"] = r.edges;
  j["cycles"] = r.cycles;
  j["energy"] = r.energy;
  j["non_metric"] = r.non_metric;
  j["cells_in"] = detail::arr3(r.cells_in);
  j["cells_out"] = detail::arr3(r.cells_out);
  j["size_in"] = detail::vec3(r.size_in);
  j["size_out"] = detail::vec3(r.size_out);
  j["timings_ms"] = r.timings_ms;
  j["output"] = {{"vertices", r.vertices_out}, {"triangles", r.triangles_out}};
  j["checked"] = r.checked;
  j["boundary_edges"] = r.checked ? nlohmann::json{{"in", r.boundary_edges_in},
                                                   {"out", r.boundary_edges_out},
                                                   {"new", r.boundary_edges_new()}}
                                  : nlohmann::json(nullptr);
  j["weld_tolerance"] = {{"relative", r.weld_tolerance}, {"measured", r.weld_tolerance_measured}};
  const Placement& p = r.placement;
  j["pivot"] = {{"modes", {pivot_name(p.modes[0]), pivot_name(p.modes[1]), pivot_name(p.modes[2])}},
                {"point", detail::vec3(p.pivot)},
                {"translation", detail::vec3(p.translation)},
                {"low_end_cells", detail::arr3(p.low_cells)}};
  j["exact"] = {{"applied", r.exact}, {"scale", detail::vec3(r.scale)}, {"size_nearest", detail::vec3(r.size_nearest)}};
  j["seam_energy"] = seam_energy_name(r.seam_energy);
  j["sample_spacing"] = r.sample_spacing;
  j["seam_tolerance"] = r.seam_tolerance;
  j["max_seam_mismatch"] = r.max_seam_mismatch;
  j["seams"] = nlohmann::json::array();
  for (const SeamReport& s : r.seams)
    j["seams"].push_back({{"cells", {detail::arr3(s.cell_a), detail::arr3(s.cell_b)}},
                          {"labels", {detail::arr3(s.label_a), detail::arr3(s.label_b)}},
                          {"mismatch", s.mismatch},
                          {"outer", s.outer},
                          {"offset", s.offset}});
  j["warnings"] = nlohmann::json::array();
  for (const ResultWarning& w : r.warnings) j["warnings"].push_back({{"check", w.check}, {"message", w.message}});
  j["seams_moved"] = r.seams_moved;
  j["plane_offsets"] = {r.plane_offsets[0], r.plane_offsets[1], r.plane_offsets[2]};
  j["parts"] = nlohmann::json::array();
  for (const PartReport& p : r.parts)
    j["parts"].push_back({{"axis", p.axis + 1},
                          {"cells", {p.first + 1, p.last + 1}},
                          {"anchor", part_anchor_name(p.anchor)},
                          {"shift", p.shift},
                          {"half", p.half}});
  return j;
}

}  // namespace restitch
