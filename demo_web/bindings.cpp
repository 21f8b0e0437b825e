// demo_web/bindings.cpp - embind bindings of restitch for the browser demo and its node tests.
//
// What it does. One `Session` object holds a model (loaded from glTF bytes or
// generated from a bundled sample), its analysis and the retarget state, so a
// slider move only pays for the retarget itself. JavaScript sees:
//
//   version() -> string
//   samples() -> [{name, description, units, parameters: [{name, value, min, max, integer, help}]}]
//   policies() -> {descriptors: [...], matchers: [...], label_spaces: [...]}
//   new Session()
//     .loadGltf(Uint8Array)              -> {ok, vertices, triangles, warnings[]} | error
//     .loadSample(name, {param: value})  -> {ok, vertices, triangles, warnings[], generators} | error
//     .analyze(descriptor, matcher, onProgress(stage, fraction)) -> {ok, analysis, extras} | error
//     .retarget(du, dv, dw, labelSpace)  -> {ok, report, out_cells, grid, label_shifts, cell_labels, face_labels}
//     .mesh(which)                       -> {positions, normals, uvs, colors, indices, groups[]} ("input"|"result")
//     .saveGlb(which)                    -> {ok, bytes: Uint8Array} | error
//     .delete()                          (embind: frees the session)
//   An error is {ok: false, code: "parse_error", message: "..."}; nothing throws.
//
// Contract. Typed arrays handed out are copies (JS owns them; they survive
// memory growth). `mesh()` orders faces by group and gives one draw range per
// group ({start, count, material, colors}); `face_labels` is in that same
// order. Positions are model units. Deterministic: the same calls give the
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
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/mesh.hpp"
#include "restitch/retarget.hpp"
#include "restitch/samples/samples.hpp"

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

// ---- the run-time choice of analysis policies: a closed set of instantiations (style.md) -------------------------

using AnalysisVariant =
    std::variant<AnalysisOptions<ShotDescriptor, BruteForceMatcher>, AnalysisOptions<ShotDescriptor, ReducedMatcher>,
                 AnalysisOptions<FpfhDescriptor, BruteForceMatcher>, AnalysisOptions<FpfhDescriptor, ReducedMatcher>>;

std::optional<AnalysisVariant> analysis_options(const std::string& descriptor, const std::string& matcher) {
  const bool shot = descriptor == "shot", fpfh = descriptor == "fpfh";
  const bool brute = matcher == "brute_force", reduced = matcher == "reduced";
  if (shot && brute) return AnalysisVariant(AnalysisOptions<ShotDescriptor, BruteForceMatcher>{});
  if (shot && reduced) return AnalysisVariant(AnalysisOptions<ShotDescriptor, ReducedMatcher>{});
  if (fpfh && brute) return AnalysisVariant(AnalysisOptions<FpfhDescriptor, BruteForceMatcher>{});
  if (fpfh && reduced) return AnalysisVariant(AnalysisOptions<FpfhDescriptor, ReducedMatcher>{});
  return std::nullopt;
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
    Result<samples::SampleModel> s = samples::generate(name, values);
    if (!s) return status_object(s.status());
    val generators = val::array();  // the sample's true repeats (model units): the tests' known answer
    for (const Eigen::Vector3d& g : s->generators) generators.call<void>("push", vec3(g));
    val out = adopt(std::move(s->mesh), {});
    out.set("generators", generators);
    return out;
  }

  val analyze(const std::string& descriptor, const std::string& matcher, val on_progress) {
    if (!input_) return status_object(error(StatusCode::invalid_argument, "load a model before analysing it"));
    std::optional<AnalysisVariant> options = analysis_options(descriptor, matcher);
    if (!options)
      return status_object(error(StatusCode::invalid_argument, "unknown descriptor '" + descriptor + "' or matcher '" +
                                                                   matcher +
                                                                   "'; descriptors: shot, fpfh; matchers: "
                                                                   "brute_force, reduced"));
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
    Result<Analysis> a = std::visit([&](const auto& o) { return restitch::analyze(*input_, o, progress); }, *options);
    if (!a) return status_object(a.status());
    analysis_ = std::make_unique<Analysis>(std::move(*a));
    val out = val::object();
    out.set("ok", true);
    out.set("analysis", analysis_json(*analysis_));
    out.set("extras", analysis_extras(*analysis_));
    return out;
  }

  val retarget(int du, int dv, int dw, const std::string& label_space) {
    if (!input_ || !analysis_)
      return status_object(error(StatusCode::invalid_argument, "analyse the model before resizing it"));
    const Eigen::Array3i steps(du, dv, dw);
    if ((steps.abs() > max_steps).any())
      return status_object(
          error(StatusCode::too_large, "the demo allows at most " + std::to_string(max_steps) + " steps per axis"));
    if (!steps.isZero() && analysis_->lattice.principal_count() == 0)
      return status_object(error(StatusCode::no_repetition,
                                 "no repetition was found in this model, so there is nothing to resize along"));
    Result<RetargetResult> r = error(StatusCode::internal, "no retargeter");
    if (label_space == "lattice") {
      if (!std::holds_alternative<Retargeter<LatticeLabels>>(retargeter_))
        retargeter_.emplace<Retargeter<LatticeLabels>>(*input_, *analysis_, retarget_options());
      r = std::get<Retargeter<LatticeLabels>>(retargeter_).retarget(steps);
    } else if (label_space == "regular") {
      if (!std::holds_alternative<Retargeter<RegularLabels>>(retargeter_))
        retargeter_.emplace<Retargeter<RegularLabels>>(*input_, *analysis_, retarget_options());
      r = std::get<Retargeter<RegularLabels>>(retargeter_).retarget(steps);
    } else {
      return status_object(error(StatusCode::invalid_argument,
                                 "unknown label space '" + label_space + "'; label spaces: lattice, regular"));
    }
    if (!r) return status_object(r.status());
    result_ = std::make_unique<RetargetResult>(std::move(*r));
    return retarget_answer(*result_, label_space);
  }

  val mesh(const std::string& which) const {
    const Mesh* m = which == "result"  ? (result_ ? &result_->mesh : nullptr)
                    : which == "input" ? input_.get()
                                       : nullptr;
    if (!m) return status_object(error(StatusCode::invalid_argument, "no '" + which + "' mesh in this session"));
    return mesh_arrays(*m);
  }

  val save_glb(const std::string& which) const {
    const Mesh* m = which == "result"  ? (result_ ? &result_->mesh : nullptr)
                    : which == "input" ? input_.get()
                                       : nullptr;
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

  static RetargetOptions retarget_options() {
    RetargetOptions o;
    o.face_labels = true;
    return o;
  }

  void clear_retarget() {
    retargeter_.emplace<std::monostate>();
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
    val w = val::array();
    for (const std::string& s : warnings) w.call<void>("push", s);
    out.set("warnings", w);
    const BoundingBox box = bounding_box(*input_);
    out.set("bbox_min", vec3(box.min));
    out.set("bbox_max", vec3(box.max));
    return out;
  }

  // The fields of `restitch analyze --json`, model units.
  static val analysis_json(const Analysis& a) {
    val j = val::object();
    j.set("scale", a.normalization.scale);
    j.set("features", double(a.features.size()));
    val dom = val::array();
    for (const DominantOffset& d : a.dominant) {
      val o = val::object();
      o.set("offset", vec3(a.normalization.to_model_offset(d.offset)));
      o.set("votes", double(d.votes));
      o.set("significant", d.significant);
      dom.call<void>("push", o);
    }
    j.set("dominant_offsets", dom);
    val pr = val::array();
    for (const Eigen::Vector3d& v : a.principal_model_units()) pr.call<void>("push", vec3(v));
    j.set("principal_offsets", pr);
    val dummies = val::array();
    for (int c = 0; c < 3; ++c)
      if (a.lattice.dummy[std::size_t(c)]) dummies.call<void>("push", vec3(a.lattice.A.col(c)));
    j.set("dummy_directions", dummies);
    val cells = val::array();
    for (int c = 0; c < 3; ++c) cells.call<void>("push", a.lattice.cells(c));
    j.set("lattice_cells", cells);
    val sp = val::object();
    sp.set("top7", a.sparsity.top7);
    sp.set("top20", a.sparsity.top20);
    j.set("sparsity", sp);
    val t = val::object();
    double total = 0;
    for (const auto& [stage, ms] : a.timings_ms) t.set(stage, ms), total += ms;
    t.set("total", total);
    j.set("timings_ms", t);
    return j;
  }

  // What the page draws besides the JSON: the lattice and the raw offsets (normalized) of the histogram view.
  static val analysis_extras(const Analysis& a) {
    val e = val::object();
    e.set("descriptor", a.descriptor_name);
    e.set("matcher", a.matcher_name);
    e.set("detector", a.detector_name);
    val lat = val::object();
    val cols = val::array();
    for (int c = 0; c < 3; ++c) cols.call<void>("push", vec3(a.lattice.A.col(c)));
    lat.set("axes", cols);
    lat.set("origin", vec3(a.lattice.origin));
    val dummy = val::array();
    for (int c = 0; c < 3; ++c) dummy.call<void>("push", bool(a.lattice.dummy[std::size_t(c)]));
    lat.set("dummy", dummy);
    e.set("lattice", lat);
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

  // The report (the figures of the paper's captions), the label grid and labels, and per face its label.
  static val retarget_answer(const RetargetResult& r, const std::string& label_space) {
    const RetargetReport& rep = r.report;
    val out = val::object();
    out.set("ok", true);
    val report = val::object();
    report.set("label_space", label_space);
    report.set("nodes", rep.nodes);
    report.set("labels", rep.labels);
    report.set("edges", rep.edges);
    report.set("cycles", rep.cycles);
    report.set("energy", rep.energy);
    report.set("regions", double(rep.regions));
    report.set("triangles_in", double(rep.triangles_in));
    report.set("triangles_out", double(rep.triangles_out));
    report.set("size_in", vec3(rep.size_in));
    report.set("size_out", vec3(rep.size_out));
    val t = val::object();
    for (const auto& [stage, ms] : rep.timings_ms) t.set(stage, ms);
    report.set("timings_ms", t);
    val ints = val::array();
    for (int a = 0; a < 3; ++a) ints.call<void>("push", rep.grid_steps(a));
    report.set("grid_steps", ints);
    out.set("report", report);
    val cells = val::array();
    for (int a = 0; a < 3; ++a) cells.call<void>("push", rep.out_cells(a));
    out.set("out_cells", cells);
    val grid = val::object();
    val cols = val::array();
    for (int c = 0; c < 3; ++c) cols.call<void>("push", vec3(r.grid.A.col(c)));
    grid.set("axes", cols);
    grid.set("origin", vec3(r.grid.origin));
    out.set("grid", grid);
    std::vector<std::int32_t> shifts(r.labels.size() * 3);
    for (std::size_t l = 0; l < r.labels.size(); ++l)
      for (int a = 0; a < 3; ++a) shifts[3 * l + std::size_t(a)] = r.labels[l](a);
    out.set("label_shifts", typed_array("Int32Array", shifts.data(), shifts.size()));
    out.set("cell_labels", typed_array("Int32Array", r.cell_labels.data(), r.cell_labels.size()));
    const std::vector<std::uint32_t> order = face_order(r.mesh);
    std::vector<std::int32_t> face_label(order.size(), 0);
    if (r.face_labels.size() == order.size())
      for (std::size_t q = 0; q < order.size(); ++q) face_label[q] = r.face_labels[order[q]];
    out.set("face_labels", typed_array("Int32Array", face_label.data(), face_label.size()));
    return out;
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
      o.set("name", m.groups[g].name);
      groups.call<void>("push", o);
      start += count;
    }
    out.set("groups", groups);
    return out;
  }

  std::unique_ptr<Mesh> input_;
  std::unique_ptr<Analysis> analysis_;
  // Refers to *input_ and *analysis_ (kept at stable addresses): reset before either changes.
  std::variant<std::monostate, Retargeter<LatticeLabels>, Retargeter<RegularLabels>> retargeter_;
  std::unique_ptr<RetargetResult> result_;
};

// ---- free functions -----------------------------------------------------------------------------------------------

std::string version() { return "restitch 0.1.0"; }

val samples_catalog() {
  val list = val::array();
  for (const samples::SampleInfo& s : samples::catalog()) {
    val o = val::object();
    o.set("name", s.name);
    o.set("description", s.description);
    o.set("units", s.units);
    val params = val::array();
    for (const samples::Parameter& p : s.parameters) {
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
  val d = val::array(), m = val::array(), l = val::array();
  d.call<void>("push", std::string("shot"));
  d.call<void>("push", std::string("fpfh"));
  m.call<void>("push", std::string("brute_force"));
  m.call<void>("push", std::string("reduced"));
  l.call<void>("push", std::string("lattice"));
  l.call<void>("push", std::string("regular"));
  o.set("descriptors", d);
  o.set("matchers", m);
  o.set("label_spaces", l);
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
      .function("analyze", &Session::analyze)
      .function("retarget", &Session::retarget)
      .function("mesh", &Session::mesh)
      .function("saveGlb", &Session::save_glb);
}
