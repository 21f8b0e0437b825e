// demo_web/bindings.cpp - embind bindings of restitch for the browser demo and its node tests.
//
// What it does. One `Session` object holds a model (loaded from glTF bytes or
// generated from a bundled sample), its analysis and the retarget state, so a
// slider move only pays for the retarget itself. JavaScript sees:
//
//   version() -> "restitch X.Y.Z"
//   samples() -> [{name, description, units, parameters: [{name, value, min, max, integer, help}]}]
//   policies() -> {descriptors: [...], matchers: [...], detectors: [...], label_spaces: [...], pivots: [...],
//                  seam_energies: [...]}
//                                         (each list: the default first)
//   new Session()
//     .loadGltf(Uint8Array)              -> {ok, vertices, triangles, bbox_min, bbox_max, warnings[]} | error
//     .loadSample(name, {param: value})  -> the same plus generators (the sample's true repeats) | error
//     .analyze(descriptor, matcher, [detector,] onProgress(stage, fraction)) -> {ok, analysis, extras} | error
//                                           (detector: "histogram" when not given)
//     .promote([[x, y, z], ...])         -> {ok, analysis, extras} | error   (model units, at most three)
//                                           makes these offsets the first principal offsets, in order, and
//                                           refits the lattice (restitch::promote_offsets_named); [] goes back
//                                           to the detected ones. Resize steps then follow the new principal
//                                           offsets. A refused request leaves the analysis and the last
//                                           result as they were.
//     .retarget(s1, s2, s3, labelSpace[, pivot]) -> {ok, report, grid, label_shifts, cell_labels, face_labels} | error
//                                           pivot: what stays put, "origin" (default), "min", "center" or "max",
//                                           or three of them for x,y,z ("min,origin,max"); restitch/placement.hpp.
//                                           report.pivot says which point stayed and the translation.
//     .retarget(s1, s2, s3, labelSpace, pivot, seamEnergy) -> the same, solved with seamEnergy
//                                           ("descriptor", the default, or "geometry"; docs/method.md 2.4b),
//                                           plus seam_faces: Uint8Array, 1 for each face (face order) within the
//                                           slab of a seam whose mismatch passes the tolerance (docs/method.md
//                                           2.8), and open_edges: Float32Array, two corners (x, y, z) per open
//                                           edge of the result that the input does not have (the result
//                                           check, docs/method.md 2.11), so the page can draw them red.
//     .prepare(labelSpace, seamEnergy)   -> {ok, ms} | error: builds what the next .retarget with these
//                                           policies needs (the Retargeter: grid, cell descriptors, stitch
//                                           cache) and runs one resize per principal offset (+1 along it) that it throws away, so
//                                           the first slider move pays only for the resize, warm.
//     .mesh(which)                       -> {ok, positions, normals?, uvs?, colors?, indices, groups[]} | error
//                                           (which: "input" | "result")
//     .saveGlb(which)                    -> {ok, bytes: Uint8Array} | error
//     .delete()                          (embind: frees the session)
//   An error is {ok: false, code: "parse_error", message: "..."}; nothing throws.
//
// The figures are the library's own, not a copy: `analysis` is exactly what
// `restitch analyze --json` prints (restitch/io/json_report.hpp, model
// units) and `report` what `restitch resize --json` prints (retarget_json plus
// steps_principal and label_space), each converted to a JS object once.
// `extras` holds what only the page draws: the raw match offsets and the
// dominant offsets in normalized units (the histogram view), the detector's
// name and the number of histogram peaks. Policies are chosen by name
// through restitch/runtime.hpp; the retarget steps s1..s3 are steps along the
// principal offsets v1..v3 in the order of `analysis.principal_offsets`
// (restitch::lattice_steps_from_principal), zeros for the ones a model does not have.
//
// Contract. Typed arrays handed out are copies (JS owns them; they survive
// memory growth). `mesh()` orders faces by group and gives one draw range per
// group ({start, count, material, colors, name}); `face_labels` is in that same
// order. `cell_labels` is in the linear order of the output cells
// (i + U * (j + V * k), report.cells_out = [U, V, W]); `grid` = {axes, origin}
// is the label grid in model units. Deterministic: the same calls give the
// same bytes. No threads.
//
// Cost. loadGltf/loadSample: linear in the model. analyze: the analysis (see
// restitch/analysis.hpp). retarget: the first call per label space builds the
// Retargeter (cell descriptor sets, the stitcher's cache); every call builds
// and solves the labelling and stitches (restitch/retarget.hpp), plus one
// copy of the output into JS.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <set>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "restitch/analyze.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/io/json_report.hpp"
#include "restitch/mesh.hpp"
#include "restitch/mesh_arrays.hpp"
#include "restitch/retarget.hpp"
#include "restitch/runtime.hpp"
#include "restitch/families/families.hpp"

#ifndef RESTITCH_VERSION_STRING
#define RESTITCH_VERSION_STRING "0.0.0"
#endif

using emscripten::val;

namespace restitch::web {

// ---- conversions --------------------------------------------------------------------------------------------------

val status_object(const Status& s) {
  val o = val::object();
  o.set("ok", s.ok());
  o.set("code", std::string(to_string(s.code())));
  o.set("message", s.message());
  return o;
}

// A JSON report as a JS object: one parse, no field written twice.
val js_object(const nlohmann::json& j) { return val::global("JSON").call<val>("parse", j.dump()); }

template <class T>
val typed_array(const char* type, const T* data, std::size_t n) {
  // Copy out of the wasm heap: a view would die with the next memory growth.
  return val::global(type).new_(emscripten::typed_memory_view(n, data)).template call<val>("slice");
}

val vec3(const Eigen::Vector3d& v) {
  val a = val::array();
  for (int k = 0; k < 3; ++k) a.call<void>("push", v(k));
  return a;
}

val string_array(const std::vector<std::string>& v) {
  val a = val::array();
  for (const std::string& s : v) a.call<void>("push", s);
  return a;
}

// ---- the session --------------------------------------------------------------------------------------------------

class Session {
 public:
  val load_gltf(val bytes) {
    const std::vector<std::uint8_t> data = emscripten::convertJSArrayToNumberVector<std::uint8_t>(bytes);
    GltfLoadReport report;
    Result<Mesh> m = load_gltf_from_memory(data.data(), data.size(), "", &report);
    if (!m) return status_object(m.status());
    return adopt(std::move(*m), report.warnings);
  }

  // A mesh given as arrays (world space, model units), as a three.js BufferGeometry holds it:
  //   {positions: Float32Array (x, y, z per vertex), indices: Uint32Array (3 per triangle),
  //    normals?: Float32Array, uvs?: [Float32Array (u, v per vertex, glTF convention)...],
  //    colors?: Float32Array (r, g, b, a per vertex, linear),
  //    groups?: [{start, count, material?, name?}] (ranges of `indices`, in order, covering it; one group when
  //             absent)}
  // A vertex used by faces of two groups is copied into each (restitch::Mesh keeps groups apart).
  val load_arrays(val arrays) {
    Result<Mesh> m = mesh_from_arrays(arrays);
    if (!m) return status_object(m.status());
    return adopt(std::move(*m), {});
  }

  val load_sample(const std::string& name, val overrides) {
    std::map<std::string, double> values;
    if (overrides.typeOf().as<std::string>() == "object" && !overrides.isNull()) {
      const val keys = val::global("Object").call<val>("keys", overrides);
      const int n = keys["length"].as<int>();
      for (int i = 0; i < n; ++i) {
        const std::string key = keys[i].as<std::string>();
        values[key] = overrides[key].as<double>();
      }
    }
    Result<families::SampleModel> s = families::generate(name, values);
    if (!s) return status_object(s.status());
    val generators = val::array();  // the sample's true repeats (model units): the tests' known answer
    for (const Eigen::Vector3d& g : s->generators) generators.call<void>("push", vec3(g));
    val out = adopt(std::move(s->mesh), {});
    out.set("generators", generators);
    return out;
  }

  val analyze(const std::string& descriptor, const std::string& matcher, val on_progress) {
    return analyze_with(descriptor, matcher, "histogram", on_progress);
  }

  val analyze_with(const std::string& descriptor, const std::string& matcher, const std::string& detector,
                   val on_progress) {
    if (!input_) return status_object(error(StatusCode::invalid_argument, "load a model before analysing it"));
    // Report at most every whole percent per stage: each report is a postMessage.
    std::string last_stage;
    int last_pct = -1;
    const bool has_callback = on_progress.typeOf().as<std::string>() == "function";
    Progress progress([&](std::string_view stage, double f) {
      const int pct = int(std::floor(std::clamp(f, 0.0, 1.0) * 100.0));
      if (has_callback && (stage != last_stage || pct != last_pct)) {
        last_stage = std::string(stage);
        last_pct = pct;
        on_progress(last_stage, f);
      }
      return true;
    });
    analysis_.reset();
    clear_retarget();
    Result<Analysis> a = analyze_named(*input_, descriptor, matcher, detector, progress);
    if (!a) return status_object(a.status());
    analysis_ = std::make_unique<Analysis>(std::move(*a));
    return analysis_answer(*analysis_);
  }

  val promote(val offsets) {
    if (!input_ || !analysis_)
      return status_object(error(StatusCode::invalid_argument, "analyse the model before choosing its offsets"));
    if (!val::global("Array").call<bool>("isArray", offsets))
      return status_object(error(StatusCode::invalid_argument, "the offsets must be an array of [x, y, z]"));
    std::vector<Eigen::Vector3d> list;
    const int n = offsets["length"].as<int>();
    for (int i = 0; i < n; ++i) {
      const val v = offsets[i];
      const bool is3 = val::global("Array").call<bool>("isArray", v) && v["length"].as<int>() == 3;
      Eigen::Vector3d x;
      for (int k = 0; is3 && k < 3; ++k) {
        if (v[k].typeOf().as<std::string>() != "number")
          return status_object(error(StatusCode::invalid_argument, "offset " + std::to_string(i + 1) +
                                                                       " is not three numbers"));
        x(k) = v[k].as<double>();
      }
      if (!is3)
        return status_object(
            error(StatusCode::invalid_argument, "offset " + std::to_string(i + 1) + " is not three numbers"));
      list.push_back(x);
    }
    // On failure promote_offsets_named leaves *analysis_ untouched: the retargeter and result stay valid.
    if (Status s = promote_offsets_named(*input_, list, *analysis_); !s) return status_object(s);
    clear_retarget();  // it refers to the analysis as it was
    return analysis_answer(*analysis_);
  }

  val retarget(int s1, int s2, int s3, const std::string& label_space) {
    return retarget_about(s1, s2, s3, label_space, "origin");
  }

  val retarget_about(int s1, int s2, int s3, const std::string& label_space, const std::string& pivot) {
    return retarget_with(s1, s2, s3, label_space, pivot, "descriptor");
  }

  val retarget_with(int s1, int s2, int s3, const std::string& label_space, const std::string& pivot,
                    const std::string& seam_energy) {
    const std::vector<int> principal{s1, s2, s3};
    return resize_with(
        label_space, pivot, seam_energy,
        [&]() -> Status {
          if (std::max({std::abs(s1), std::abs(s2), std::abs(s3)}) > max_steps)
            return error(StatusCode::too_large,
                         "the demo allows at most " + std::to_string(max_steps) + " steps per axis");
          return lattice_steps_from_principal(*analysis_, principal).status();
        },
        [&](AnyRetargeter& r) { return r.retarget(*lattice_steps_from_principal(*analysis_, principal)); });
  }

  // Resize to a bounding-box size (model units; 0 keeps an axis): the nearest whole repeats, and with `exact`
  // a scale about the pivot to the size asked (Retargeter::retarget_to_size). The same answer as retarget.
  val retarget_to_size(double x, double y, double z, bool exact, const std::string& label_space,
                       const std::string& pivot, const std::string& seam_energy) {
    const Eigen::Vector3d size(x, y, z);
    return resize_with(
        label_space, pivot, seam_energy, [&] { return check_size_values(size); },
        [&](AnyRetargeter& r) { return r.retarget_to_size(size, exact); });
  }

  // Builds the retargeter the next resize with these policies needs (grid, cell descriptors, slabs, the
  // stitcher's cache), so that resize does not pay for it: the worker calls this right after answering an
  // analysis. {ok, ms}, or the status when the policies are unknown or the grid is refused.
  val prepare(const std::string& label_space, const std::string& seam_energy) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<SeamEnergy> energy = seam_energy_named(seam_energy);
    if (!energy) return status_object(energy.status());
    if (!input_ || !analysis_) return status_object(error(StatusCode::invalid_argument, "analyse the model first"));
    if (analysis_->principal.empty())
      return status_object(error(StatusCode::no_repetition, "no principal offset: nothing to prepare"));
    const AnyRetargeter* before = retargeter_.get();
    if (Status s = ensure_retargeter(label_space, *energy); !s) return status_object(s);
    // Warm-up, once per retargeter built (a prepare that keeps the current one has nothing to warm): one
    // resize per principal offset (+1 along it) and its conversion to JS, thrown away. The first call of a
    // code path in a fresh WebAssembly instance runs it cold (the browser compiles functions on their first
    // call, in a baseline tier, and optimises hot ones later): in Chromium the first resize took 43-59 ms of
    // the library's time against 1-8 ms for the same work later. Its result and the session's last result
    // are independent (the retargeter's caches are caches), so nothing the page sees changes.
    const bool built = retargeter_.get() != before;
    const std::size_t warm_axes = built ? std::min<std::size_t>(analysis_->principal.size(), 3) : 0;
    for (std::size_t i = 0; i < warm_axes; ++i) {
      std::vector<int> principal_steps{0, 0, 0};
      principal_steps[i] = 1;
      Result<Eigen::Array3i> warm_steps = lattice_steps_from_principal(*analysis_, principal_steps);
      if (!warm_steps) continue;
      Result<RetargetResult> warm = retargeter_->retarget(*warm_steps);
      if (!warm) continue;
      val answer = retarget_answer(*warm, *analysis_, label_space);
      val arrays = mesh_arrays(warm->mesh);
    }
    val out = val::object();
    out.set("ok", true);
    out.set("ms", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    return out;
  }

  val mesh(const std::string& which) const {
    const Mesh* m = mesh_named(which);
    if (!m) return status_object(error(StatusCode::invalid_argument, "no '" + which + "' mesh in this session"));
    return mesh_arrays(*m);
  }

  val save_glb(const std::string& which) const {
    const Mesh* m = mesh_named(which);
    if (!m) return status_object(error(StatusCode::invalid_argument, "no '" + which + "' mesh in this session"));
    Result<std::vector<std::uint8_t>> bytes = save_glb_to_memory(*m);
    if (!bytes) return status_object(bytes.status());
    val out = val::object();
    out.set("ok", true);
    out.set("bytes", typed_array("Uint8Array", bytes->data(), bytes->size()));
    return out;
  }

 private:
  static constexpr int max_steps = 64;

  // What every resize does: the policies and pivot by name, `check()` (the request against the analysis)
  // before anything is built, the retargeter for these policies about the pivot, `run(retargeter)`, and the
  // result kept and answered. A refused request changes nothing.
  template <class Check, class Run>
  val resize_with(const std::string& label_space, const std::string& pivot, const std::string& seam_energy,
                  Check&& check, Run&& run) {
    Result<SeamEnergy> energy = seam_energy_named(seam_energy);
    if (!energy) return status_object(energy.status());
    Result<Pivots> pivots = parse_pivots(pivot);
    if (!pivots) return status_object(pivots.status());
    if (!input_ || !analysis_)
      return status_object(error(StatusCode::invalid_argument, "analyse the model before resizing it"));
    if (Status s = check(); !s) return status_object(s);
    if (Status s = ensure_retargeter(label_space, *energy); !s) return status_object(s);
    retargeter_->set_pivot(*pivots);
    Result<RetargetResult> r = run(*retargeter_);
    if (!r) return status_object(r.status());
    result_ = std::make_unique<RetargetResult>(std::move(*r));
    return retarget_answer(*result_, *analysis_, label_space);
  }

  // The retargeter for these policies, built unless it is the current one. Built aside: an unknown name or
  // a grid too large keeps the current one usable.
  Status ensure_retargeter(const std::string& label_space, SeamEnergy energy) {
    if (retargeter_ && label_space == retargeter_space_ && energy == retargeter_energy_) return {};
    auto next = std::make_unique<AnyRetargeter>(*input_, *analysis_, label_space, retarget_options(energy));
    RESTITCH_TRY(next->status());
    retargeter_ = std::move(next);
    retargeter_space_ = label_space;
    retargeter_energy_ = energy;
    return {};
  }

  static RetargetOptions retarget_options(SeamEnergy energy) {
    RetargetOptions o;
    o.face_labels = true;
    o.seam_energy = energy;
    return o;
  }

  const Mesh* mesh_named(const std::string& which) const {
    if (which == "result") return result_ ? &result_->mesh : nullptr;
    if (which == "input") return input_.get();
    return nullptr;
  }

  void clear_retarget() {
    retargeter_.reset();
    retargeter_space_.clear();
    result_.reset();
  }

  val adopt(Mesh mesh, const std::vector<std::string>& warnings) {
    analysis_.reset();
    clear_retarget();
    input_ = std::make_unique<Mesh>(std::move(mesh));
    val out = val::object();
    out.set("ok", true);
    out.set("vertices", double(input_->vertex_count()));
    out.set("triangles", double(input_->triangle_count()));
    out.set("warnings", string_array(warnings));
    const BoundingBox box = bounding_box(*input_);
    out.set("bbox_min", vec3(box.min));
    out.set("bbox_max", vec3(box.max));
    return out;
  }

  static val analysis_answer(const Analysis& a) {
    val out = val::object();
    out.set("ok", true);
    out.set("analysis", js_object(analysis_json(a)));
    out.set("extras", analysis_extras(a));
    return out;
  }

  // What the page draws besides the JSON: the raw offsets (normalized) of the histogram view.
  static val analysis_extras(const Analysis& a) {
    val e = val::object();
    e.set("detector", a.detector_name);
    std::vector<float> offsets;
    offsets.reserve(a.matches.size() * 3);
    for (std::size_t i = 0; i < a.matches.size(); ++i) {
      const Match& m = a.matches[i];
      if (m.target < 0) continue;
      const auto d = (a.features.points.row(m.target) - a.features.points.row(Eigen::Index(i))).eval();
      offsets.insert(offsets.end(), {d(0), d(1), d(2)});
    }
    e.set("match_offsets", typed_array("Float32Array", offsets.data(), offsets.size()));
    val dom = val::array();
    for (const DominantOffset& d : a.dominant) dom.call<void>("push", vec3(d.offset));
    e.set("dominant_normalized", dom);
    e.set("histogram_peaks", double(a.histogram_peaks));
    return e;
  }

  // The report as `restitch resize --json` prints it, the label grid and labels, and per face its label.
  static val retarget_answer(const RetargetResult& r, const Analysis& a, const std::string& label_space) {
    nlohmann::json j = retarget_json(r.report);
    j["steps_principal"] = principal_steps_from_lattice(a, r.report.steps);
    j["label_space"] = label_space;
    val out = val::object();
    out.set("ok", true);
    out.set("report", js_object(j));
    val grid = val::object();
    val cols = val::array();
    for (int c = 0; c < 3; ++c) cols.call<void>("push", vec3(r.grid.A.col(c)));
    grid.set("axes", cols);
    grid.set("origin", vec3(r.grid.origin));
    out.set("grid", grid);
    std::vector<std::int32_t> shifts(r.labels.size() * 3);
    for (std::size_t l = 0; l < r.labels.size(); ++l)
      for (int k = 0; k < 3; ++k) shifts[3 * l + std::size_t(k)] = r.labels[l](k);
    out.set("label_shifts", typed_array("Int32Array", shifts.data(), shifts.size()));
    out.set("cell_labels", typed_array("Int32Array", r.cell_labels.data(), r.cell_labels.size()));
    const std::vector<std::uint32_t> order = face_order(r.mesh);
    std::vector<std::int32_t> face_label(order.size(), 0);
    if (r.face_labels.size() == order.size())
      for (std::size_t q = 0; q < order.size(); ++q) face_label[q] = r.face_labels[order[q]];
    out.set("face_labels", typed_array("Int32Array", face_label.data(), face_label.size()));
    const std::vector<std::uint8_t> bad = seam_faces(r);
    std::vector<std::uint8_t> seam_face(order.size(), 0);
    for (std::size_t q = 0; q < order.size(); ++q) seam_face[q] = bad[order[q]];
    out.set("seam_faces", typed_array("Uint8Array", seam_face.data(), seam_face.size()));
    std::vector<float> open_edges;  // the result check's new open edges: two corners each
    for (const std::array<Eigen::Vector3f, 2>& e : r.report.open_edges)
      for (const Eigen::Vector3f& p : e) open_edges.insert(open_edges.end(), {p.x(), p.y(), p.z()});
    out.set("open_edges", typed_array("Float32Array", open_edges.data(), open_edges.size()));
    return out;
  }

  // Per face: 1 when its centroid lies within the slab (2 sample spacings) of a seam over the tolerance.
  static std::vector<std::uint8_t> seam_faces(const RetargetResult& r) {
    const Mesh& m = r.mesh;
    std::vector<std::uint8_t> flag(m.triangle_count(), 0);
    const RetargetReport& rep = r.report;
    std::set<std::array<int, 6>> over;
    for (const SeamReport& s : rep.seams)
      if (s.mismatch > rep.seam_tolerance) {
        over.insert({s.cell_a[0], s.cell_a[1], s.cell_a[2], s.cell_b[0], s.cell_b[1], s.cell_b[2]});
        over.insert({s.cell_b[0], s.cell_b[1], s.cell_b[2], s.cell_a[0], s.cell_a[1], s.cell_a[2]});
      }
    if (over.empty()) return flag;
    const Eigen::Matrix3d Ainv = r.grid.A.inverse();
    double width[3];
    for (int a = 0; a < 3; ++a) width[a] = 2 * rep.sample_spacing * Ainv.row(a).norm();
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int corner = 0; corner < 3; ++corner) c += m.V.row(m.F(f, corner)).cast<double>().transpose() / 3.0;
      const Eigen::Vector3d t = Ainv * (c - r.grid.origin);
      const Eigen::Array3i cell = rep.cell_of(t);  // with the seams' planes as they lie (method.md 2.9)
      for (int a = 0; a < 3 && !flag[std::size_t(f)]; ++a)
        for (int side = -1; side <= 1; side += 2) {
          Eigen::Array3i n = cell;
          n[a] += side;
          const double plane = rep.plane(a, cell[a] + (side > 0 ? 1 : 0));
          const double gap = side > 0 ? plane - t[a] : t[a] - plane;  // negative beyond the plane (overhang)
          if (gap <= width[a] && over.count({cell[0], cell[1], cell[2], n[0], n[1], n[2]})) {
            flag[std::size_t(f)] = 1;
            break;
          }
        }
    }
    return flag;
  }

  // Faces ordered by group (stable), so one draw range per group.
  static std::vector<std::uint32_t> face_order(const Mesh& m) {
    const std::size_t nf = m.triangle_count(), ng = m.groups.size();
    std::vector<std::uint32_t> start(ng + 1, 0), order(nf);
    for (std::size_t f = 0; f < nf; ++f) ++start[std::size_t(m.FG(Eigen::Index(f))) + 1];
    for (std::size_t g = 0; g < ng; ++g) start[g + 1] += start[g];
    for (std::size_t f = 0; f < nf; ++f) order[start[std::size_t(m.FG(Eigen::Index(f)))]++] = std::uint32_t(f);
    return order;
  }

  static val mesh_arrays(const Mesh& m) {
    val out = val::object();
    out.set("ok", true);
    const std::size_t nv = m.vertex_count();
    out.set("positions", typed_array("Float32Array", m.V.data(), nv * 3));
    if (m.N.rows()) out.set("normals", typed_array("Float32Array", m.N.data(), nv * 3));
    if (!m.UV.empty()) out.set("uvs", typed_array("Float32Array", m.UV[0].data(), nv * 2));
    val uv_sets = val::array();  // every set, TEXCOORD_0 first (uvs is the first one)
    for (const MatrixX2f& uv : m.UV) uv_sets.call<void>("push", typed_array("Float32Array", uv.data(), nv * 2));
    out.set("uvSets", uv_sets);
    if (m.C.rows()) out.set("colors", typed_array("Float32Array", m.C.data(), nv * 4));
    const std::vector<std::uint32_t> order = face_order(m);
    std::vector<std::uint32_t> idx(order.size() * 3);
    for (std::size_t q = 0; q < order.size(); ++q)
      for (int k = 0; k < 3; ++k) idx[3 * q + std::size_t(k)] = m.F(Eigen::Index(order[q]), k);
    out.set("indices", typed_array("Uint32Array", idx.data(), idx.size()));
    val groups = val::array();
    std::size_t start = 0;
    for (std::size_t g = 0; g < m.groups.size(); ++g) {
      std::size_t count = 0;
      while (start + count < order.size() && m.FG(Eigen::Index(order[start + count])) == g) ++count;
      val o = val::object();
      o.set("start", double(start * 3));
      o.set("count", double(count * 3));
      o.set("material", m.groups[g].material);
      o.set("colors", m.groups[g].attributes.color_components > 0);
      o.set("group", double(g));  // the index of the input's group it comes from (stitching keeps groups)
      o.set("name", m.groups[g].name);
      groups.call<void>("push", o);
      start += count;
    }
    out.set("groups", groups);
    return out;
  }

  template <class T>
  static Result<std::vector<T>> numbers(const val& arrays, const char* name, bool required) {
    const val v = arrays[name];
    if (v.isUndefined() || v.isNull()) {
      if (required) return error(StatusCode::invalid_argument, std::string("the mesh arrays have no ") + name);
      return std::vector<T>{};
    }
    if (!v["length"].isNumber())
      return error(StatusCode::invalid_argument, std::string(name) + " is not an array of numbers");
    return emscripten::convertJSArrayToNumberVector<T>(v);
  }

  // The JavaScript arrays as restitch::MeshArrays (restitch/mesh_arrays.hpp checks and builds the mesh).
  static Result<Mesh> mesh_from_arrays(const val& arrays) {
    if (arrays.typeOf().as<std::string>() != "object" || arrays.isNull())
      return error(StatusCode::invalid_argument, "give the mesh as {positions, indices, ...}");
    MeshArrays a;
    Result<std::vector<float>> pos = numbers<float>(arrays, "positions", true), nrm = numbers<float>(arrays, "normals", false),
                               col = numbers<float>(arrays, "colors", false);
    Result<std::vector<std::uint32_t>> idx = numbers<std::uint32_t>(arrays, "indices", true);
    for (const Status& s : {pos.status(), idx.status(), nrm.status(), col.status()})
      if (!s) return s;
    a.positions = std::move(*pos);
    a.indices = std::move(*idx);
    a.normals = std::move(*nrm);
    a.colors = std::move(*col);
    auto bad = [](const std::string& what) { return error(StatusCode::invalid_argument, what); };
    const val uv_list = arrays["uvs"];
    if (!uv_list.isUndefined() && !uv_list.isNull()) {
      if (!val::global("Array").call<bool>("isArray", uv_list)) return bad("uvs: an array of Float32Array, one per set");
      for (int k = 0, n = uv_list["length"].as<int>(); k < n; ++k)
        a.uvs.push_back(emscripten::convertJSArrayToNumberVector<float>(uv_list[k]));
    }
    const val groups = arrays["groups"];
    if (!groups.isUndefined() && !groups.isNull()) {
      if (!val::global("Array").call<bool>("isArray", groups)) return bad("groups: an array of {start, count}");
      for (int g = 0, n = groups["length"].as<int>(); g < n; ++g) {
        const val o = groups[g];
        const std::string at = "groups[" + std::to_string(g) + "]";
        if (o.typeOf().as<std::string>() != "object" || !o["start"].isNumber() || !o["count"].isNumber())
          return bad(at + ": not {start, count}");
        const double start = o["start"].as<double>(), count = o["count"].as<double>();
        if (!(start >= 0 && count >= 0 && start == std::floor(start) && count == std::floor(count)))
          return bad(at + ": start and count are whole numbers");
        a.groups.push_back({std::size_t(start), std::size_t(count), o["material"].isNumber() ? o["material"].as<int>() : -1,
                            o["name"].isString() ? o["name"].as<std::string>() : ""});
      }
    }
    return restitch::mesh_from_arrays(a);
  }

  std::unique_ptr<Mesh> input_;
  std::unique_ptr<Analysis> analysis_;
  // Refers to *input_ and *analysis_ (kept at stable addresses): reset before either changes.
  std::unique_ptr<AnyRetargeter> retargeter_;
  std::string retargeter_space_;
  SeamEnergy retargeter_energy_ = SeamEnergy::descriptor;
  std::unique_ptr<RetargetResult> result_;
};

// ---- free functions -----------------------------------------------------------------------------------------------

std::string version() { return "restitch " RESTITCH_VERSION_STRING; }

val samples_catalog() {
  val list = val::array();
  for (const families::SampleInfo& s : families::catalog()) {
    val o = val::object();
    o.set("name", s.name);
    o.set("description", s.description);
    o.set("units", s.units);
    val params = val::array();
    for (const families::Parameter& p : s.parameters) {
      val q = val::object();
      q.set("name", p.name);
      q.set("value", p.value);
      q.set("min", p.min);
      q.set("max", p.max);
      q.set("integer", p.integer);
      q.set("help", p.help);
      params.call<void>("push", q);
    }
    o.set("parameters", params);
    list.call<void>("push", o);
  }
  return list;
}

val policies() {
  val o = val::object();
  o.set("descriptors", string_array(descriptor_names()));
  o.set("matchers", string_array(matcher_names()));
  o.set("detectors", string_array(detector_names()));
  o.set("label_spaces", string_array(label_space_names()));
  o.set("pivots", string_array({"origin", "min", "center", "max"}));
  o.set("seam_energies", string_array(seam_energy_names()));
  return o;
}

}  // namespace restitch::web

EMSCRIPTEN_BINDINGS(restitch_web) {
  using namespace restitch::web;
  emscripten::function("version", &version);
  emscripten::function("samples", &samples_catalog);
  emscripten::function("policies", &policies);
  emscripten::class_<Session>("Session")
      .constructor<>()
      .function("loadGltf", &Session::load_gltf)
      .function("loadSample", &Session::load_sample)
      .function("loadArrays", &Session::load_arrays)
      .function("analyze", &Session::analyze)
      .function("analyze", &Session::analyze_with)
      .function("promote", &Session::promote)
      .function("retarget", &Session::retarget)
      .function("retarget", &Session::retarget_about)
      .function("retarget", &Session::retarget_with)
      .function("retargetToSize", &Session::retarget_to_size)
      .function("prepare", &Session::prepare)
      .function("mesh", &Session::mesh)
      .function("saveGlb", &Session::save_glb);
}
