// examples/python/restitch_python.cpp - the Python module `restitch` (pybind11).
//
//   import restitch
//   mesh = restitch.load("shelf.glb")                 # or restitch.Mesh(positions, triangles, ...)
//   analysis = restitch.analyze(mesh)                 # the repeats (the GIL is released meanwhile)
//   r = restitch.Retargeter(mesh, analysis)           # keeps its caches: resize as often as wanted
//   result = r.resize(steps=(2, 0))                   # or size=(1.8, 0, 0), exact=True
//   result.mesh.save("wider.glb"); result.report; result.warnings
//
// Meshes are immutable (a Mesh wraps a restitch::Mesh shared with the analyses and retargeters that use
// it); arrays come out as numpy arrays (copies). `Analysis.promote` returns a new Analysis, so a Retargeter
// never sees its analysis change. Reports are the dictionaries of `restitch analyze --json` and `restitch
// resize --json` (restitch/io/json_report.hpp). Failures raise restitch.Error with the library's message
// and `.code` (its StatusCode name). Policies are named as the command-line tool names them
// (restitch/runtime.hpp). Typings: restitch.pyi beside the module.
#define RESTITCH_GLTF_IMPLEMENTATION
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "restitch/analyze.hpp"
#include "restitch/families/families.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/io/json_report.hpp"
#include "restitch/mesh_arrays.hpp"
#include "restitch/retarget.hpp"
#include "restitch/runtime.hpp"

#ifndef RESTITCH_VERSION_STRING
#define RESTITCH_VERSION_STRING "0.0.0"
#endif

namespace py = pybind11;
using namespace pybind11::literals;
using namespace restitch;

namespace {

// restitch.Error, made at import (the module may be imported under another name, as in the Blender add-on).
PyObject* error_class = nullptr;

// Raises restitch.Error(message) with .code.
[[noreturn]] void raise(const Status& s) {
  py::object cls = py::reinterpret_borrow<py::object>(error_class);
  py::object e = cls(s.message());
  e.attr("code") = std::string(to_string(s.code()));
  PyErr_SetObject(cls.ptr(), e.ptr());
  throw py::error_already_set();
}
template <class T>
T value(Result<T> r) {
  if (!r) raise(r.status());
  return std::move(*r);
}
void ok(const Status& s) {
  if (!s) raise(s);
}

py::object to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

template <class T, class Matrix>
py::array_t<T> array_of(const Matrix& m) {
  std::vector<py::ssize_t> shape{py::ssize_t(m.rows())};
  if (m.cols() > 1) shape.push_back(py::ssize_t(m.cols()));
  py::array_t<T> out(shape);
  std::copy(m.data(), m.data() + m.size(), out.mutable_data());
  return out;
}

// A float array of shape (n, k) (or None, or (0, k)), as a flat vector; `what` names it in errors.
std::vector<float> rows(const py::object& o, py::ssize_t k, const char* what, py::ssize_t n = -1) {
  if (o.is_none()) return {};
  FloatArray a = FloatArray::ensure(o);
  if (!a || a.ndim() != 2 || a.shape(1) != k || (n >= 0 && a.shape(0) != n))
    raise(error(StatusCode::invalid_argument, std::string(what) + ": an array of shape (" +
                                                  (n >= 0 ? std::to_string(n) : std::string("n")) + ", " +
                                                  std::to_string(k) + ") is expected"));
  return std::vector<float>(a.data(), a.data() + a.size());
}

struct PyMesh {
  std::shared_ptr<const Mesh> mesh;
};

PyMesh make_mesh(const py::object& positions, const py::object& triangles, const py::object& normals,
                 const py::object& uvs, const py::object& colors, const py::object& material_ids) {
  MeshArrays a;
  a.positions = rows(positions, 3, "positions");
  const py::ssize_t nv = py::ssize_t(a.positions.size() / 3);
  auto tri = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(triangles);
  if (!tri || tri.ndim() != 2 || tri.shape(1) != 3)
    raise(error(StatusCode::invalid_argument, "triangles: an array of shape (m, 3) is expected"));
  const py::ssize_t nf = tri.shape(0);
  for (py::ssize_t i = 0; i < 3 * nf; ++i)
    if (tri.data()[i] < 0 || tri.data()[i] >= nv)
      raise(error(StatusCode::invalid_argument, "triangles: index " + std::to_string(tri.data()[i]) +
                                                     " is not a vertex (0 to " + std::to_string(nv - 1) + ")"));
  a.normals = rows(normals, 3, "normals", nv);
  a.colors = rows(colors, 4, "colors", nv);
  if (!uvs.is_none())
    for (const py::handle& uv : uvs) a.uvs.push_back(rows(py::reinterpret_borrow<py::object>(uv), 2, "uvs", nv));
  // Faces ordered by material (stable): one group per material, in ascending order.
  std::vector<int> material(std::size_t(nf), -1);
  if (!material_ids.is_none()) {
    auto m = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(material_ids);
    if (!m || m.ndim() != 1 || m.shape(0) != nf)
      raise(error(StatusCode::invalid_argument, "material_ids: one integer per triangle is expected"));
    for (py::ssize_t f = 0; f < nf; ++f) {
      if (m.data()[f] < -1 || m.data()[f] > 1 << 20)
        raise(error(StatusCode::invalid_argument, "material_ids: -1 (none) or a material index is expected"));
      material[std::size_t(f)] = int(m.data()[f]);
    }
  }
  std::vector<std::size_t> order(static_cast<std::size_t>(nf));
  for (std::size_t f = 0; f < order.size(); ++f) order[f] = f;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return material[x] < material[y]; });
  for (const std::size_t f : order) {
    if (a.groups.empty() || a.groups.back().material != material[f])
      a.groups.push_back({a.indices.size(), 0, material[f], "material " + std::to_string(material[f])});
    for (int k = 0; k < 3; ++k) a.indices.push_back(std::uint32_t(tri.data()[3 * f + std::size_t(k)]));
    a.groups.back().count += 3;
  }
  return PyMesh{std::make_shared<const Mesh>(value(mesh_from_arrays(a)))};
}

struct PyAnalysis {
  std::shared_ptr<const Mesh> mesh;
  std::shared_ptr<const Analysis> analysis;
};

py::list vectors(const std::vector<Eigen::Vector3d>& v) {
  py::list out;
  for (const Eigen::Vector3d& x : v) out.append(py::make_tuple(x.x(), x.y(), x.z()));
  return out;
}

struct PyResult {
  PyMesh mesh;
  py::object report;
};

class PyRetargeter {
 public:
  PyRetargeter(const PyMesh& mesh, const PyAnalysis& analysis, const std::string& label_space,
               const std::string& seam_energy, const std::string& pivot, bool check)
      : mesh_(mesh.mesh), analysis_(analysis.analysis), label_space_(label_space) {
    if (analysis.mesh != mesh.mesh)
      raise(error(StatusCode::invalid_argument, "the analysis was made for another mesh"));
    RetargetOptions o;
    o.seam_energy = value(seam_energy_named(seam_energy));
    o.check = check;
    Pivots p = value(parse_pivots(pivot));
    {
      py::gil_scoped_release release;
      r_ = std::make_unique<AnyRetargeter>(*mesh_, *analysis_, label_space, o);
    }
    ok(r_->status());
    r_->set_pivot(p);
  }

  PyResult resize(const py::object& steps, const py::object& size, bool exact) {
    if (steps.is_none() == size.is_none())
      raise(error(StatusCode::invalid_argument, "give steps (per principal offset) or size (x, y, z), not both"));
    Result<RetargetResult> r = error(StatusCode::internal, "no request");
    if (!steps.is_none()) {
      std::vector<int> s = steps.cast<std::vector<int>>();
      if (s.size() > 3) raise(error(StatusCode::invalid_argument, "steps: at most three, one per principal offset"));
      const Eigen::Array3i lattice = value(lattice_steps_from_principal(*analysis_, s));
      py::gil_scoped_release release;
      r = r_->retarget(lattice);
    } else {
      const std::vector<double> v = size.cast<std::vector<double>>();
      if (v.size() != 3) raise(error(StatusCode::invalid_argument, "size: three lengths x, y, z (0 keeps an axis)"));
      py::gil_scoped_release release;
      r = r_->retarget_to_size(Eigen::Vector3d(v[0], v[1], v[2]), exact);
    }
    RetargetResult out = value(std::move(r));
    nlohmann::json j = retarget_json(out.report);
    j["steps_principal"] = principal_steps_from_lattice(*analysis_, out.report.steps);
    j["label_space"] = label_space_;
    return PyResult{PyMesh{std::make_shared<const Mesh>(std::move(out.mesh))}, to_python(j)};
  }

  std::vector<int> steps_for_size(const std::vector<double>& size) const {
    if (size.size() != 3) raise(error(StatusCode::invalid_argument, "size: three lengths x, y, z (0 keeps an axis)"));
    const Eigen::Array3i lattice = value(r_->steps_for_size(Eigen::Vector3d(size[0], size[1], size[2])));
    return principal_steps_from_lattice(*analysis_, lattice);
  }

 private:
  std::shared_ptr<const Mesh> mesh_;
  std::shared_ptr<const Analysis> analysis_;
  std::string label_space_;
  std::unique_ptr<AnyRetargeter> r_;
};

}  // namespace

PYBIND11_MODULE(restitch, m) {
  m.doc() = "Resize man-made 3D models along their repeats by graph-cut stitching (restitch).";
  m.attr("__version__") = RESTITCH_VERSION_STRING;
  py::object base = py::reinterpret_borrow<py::object>(PyExc_Exception);
  py::object error_type = py::module_::import("builtins").attr("type")(
      "Error", py::make_tuple(base), py::dict("__module__"_a = "restitch", "code"_a = "internal",
                                              "__doc__"_a = "A failure of restitch: .code is the library's StatusCode "
                                                           "name (invalid_argument, parse_error, no_repetition, ...)."));
  m.attr("Error") = error_type;
  error_class = error_type.release().ptr();  // kept for the life of the process, as the module

  m.def("policies", [] {
    py::dict d;
    d["descriptors"] = descriptor_names();
    d["matchers"] = matcher_names();
    d["detectors"] = detector_names();
    d["label_spaces"] = label_space_names();
    d["seam_energies"] = seam_energy_names();
    d["pivots"] = std::vector<std::string>{"origin", "min", "center", "max"};
    return d;
  }, "The policy names, each list with its default first.");

  py::class_<PyMesh>(m, "Mesh", "A triangle mesh in model units, immutable.")
      .def(py::init(&make_mesh), py::arg("positions"), py::arg("triangles"), py::arg("normals") = py::none(),
           py::arg("uvs") = py::none(), py::arg("colors") = py::none(), py::arg("material_ids") = py::none(),
           "From arrays: positions (n, 3), triangles (m, 3), and optionally normals (n, 3), uvs (a list of (n, 2), "
           "glTF convention: v down), colors (n, 4) RGBA and material_ids (m,) (-1: none).")
      .def_property_readonly("positions", [](const PyMesh& p) { return array_of<float>(p.mesh->V); })
      .def_property_readonly("triangles", [](const PyMesh& p) { return array_of<std::uint32_t>(p.mesh->F); })
      .def_property_readonly("normals", [](const PyMesh& p) -> py::object {
        if (!p.mesh->N.rows()) return py::none();
        return array_of<float>(p.mesh->N);
      })
      .def_property_readonly("uvs", [](const PyMesh& p) {
        py::list out;
        for (const MatrixX2f& uv : p.mesh->UV) out.append(array_of<float>(uv));
        return out;
      })
      .def_property_readonly("colors", [](const PyMesh& p) -> py::object {
        if (!p.mesh->C.rows()) return py::none();
        return array_of<float>(p.mesh->C);
      })
      .def_property_readonly("material_ids", [](const PyMesh& p) {
        py::array_t<std::int32_t> out(py::ssize_t(p.mesh->triangle_count()));
        for (std::size_t f = 0; f < p.mesh->triangle_count(); ++f)
          out.mutable_data()[f] = p.mesh->groups[p.mesh->FG(Eigen::Index(f))].material;
        return out;
      }, "Per triangle, the index of its material (-1: none).")
      .def_property_readonly("group_ids", [](const PyMesh& p) { return array_of<std::uint32_t>(p.mesh->FG); },
                             "Per triangle, its group (a glTF primitive: one material, one set of attributes).")
      .def_property_readonly("material_names", [](const PyMesh& p) {
        std::vector<std::string> out;
        for (const Material& mat : p.mesh->materials) out.push_back(mat.name);
        return out;
      })
      .def_property_readonly("vertex_count", [](const PyMesh& p) { return p.mesh->vertex_count(); })
      .def_property_readonly("triangle_count", [](const PyMesh& p) { return p.mesh->triangle_count(); })
      .def_property_readonly("bounds", [](const PyMesh& p) {
        const BoundingBox b = bounding_box(*p.mesh);
        return py::make_tuple(py::make_tuple(b.min.x(), b.min.y(), b.min.z()), py::make_tuple(b.max.x(), b.max.y(), b.max.z()));
      }, "((min x, y, z), (max x, y, z)) of the vertices the triangles use.")
      .def("to_glb", [](const PyMesh& p) {
        const std::vector<std::uint8_t> bytes = value(save_glb_to_memory(*p.mesh));
        return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
      }, "The mesh as .glb bytes (a loaded file's materials, textures and extensions kept).")
      .def("save", [](const PyMesh& p, const std::string& path) { ok(save_gltf(*p.mesh, path)); }, py::arg("path"),
           "Writes .glb or .gltf (by the extension); nothing is left behind on failure.")
      .def("__repr__", [](const PyMesh& p) {
        return "<restitch.Mesh " + std::to_string(p.mesh->vertex_count()) + " vertices, " +
               std::to_string(p.mesh->triangle_count()) + " triangles>";
      });

  m.def("load", [](const std::string& path) { return PyMesh{std::make_shared<const Mesh>(value(load_gltf(path)))}; },
        py::arg("path"), "Reads a .glb or .gltf file (node transforms applied).");
  m.def("loads", [](const py::bytes& data) {
    const std::string s = data;
    return PyMesh{std::make_shared<const Mesh>(
        value(load_gltf_from_memory(reinterpret_cast<const std::uint8_t*>(s.data()), s.size())))};
  }, py::arg("data"), "Reads .glb bytes (or .gltf with embedded buffers).");
  m.def("sample", [](const std::string& name, const py::kwargs& params) {
    std::map<std::string, double> values;
    for (const auto& kv : params) values[kv.first.cast<std::string>()] = kv.second.cast<double>();
    families::SampleModel s = value(families::generate(name, values));
    return PyMesh{std::make_shared<const Mesh>(std::move(s.mesh))};
  }, py::arg("name"), "A bundled sample generated with these parameters: sample('bookshelf', columns=5).");
  m.def("samples", [] {
    std::vector<std::string> out;
    for (const families::SampleInfo& s : families::catalog()) out.push_back(s.name);
    return out;
  }, "The bundled samples' names.");

  py::class_<PyAnalysis>(m, "Analysis", "How a mesh repeats (restitch analyze); immutable.")
      .def_property_readonly("principal_offsets", [](const PyAnalysis& a) {
        return vectors(a.analysis->principal_model_units());
      }, "What steps step along, in order (model units).")
      .def_property_readonly("lattice", [](const PyAnalysis& a) {
        const nlohmann::json j = analysis_json(*a.analysis);
        py::dict d;
        d["axes"] = to_python(j["lattice_axes"]);
        d["origin"] = to_python(j["lattice_origin"]);
        d["cells"] = to_python(j["lattice_cells"]);
        d["resizable"] = to_python(j["resizable"]);
        return d;
      }, "The lattice the cells are cut on: axes (three, model units), origin, cells per axis, and which axes "
         "can be resized (the others are dummy directions).")
      .def_property_readonly("report", [](const PyAnalysis& a) { return to_python(analysis_json(*a.analysis)); },
                             "The fields of `restitch analyze --json`.")
      .def_property_readonly("candidates", [](const PyAnalysis& a) {
        return to_python(analysis_json(*a.analysis)["candidates"]);
      }, "Repeats found but not principal: promote() one to resize along it.")
      .def("promote", [](const PyAnalysis& a, const std::vector<std::array<double, 3>>& offsets) {
        auto next = std::make_shared<Analysis>(*a.analysis);
        std::vector<Eigen::Vector3d> v;
        for (const auto& o : offsets) v.emplace_back(o[0], o[1], o[2]);
        ok(promote_offsets_named(*a.mesh, v, *next));
        return PyAnalysis{a.mesh, std::move(next)};
      }, py::arg("offsets"), "A new analysis with these offsets (model units, at most three) principal first; [] goes "
                             "back to the detected ones.")
      .def("__repr__", [](const PyAnalysis& a) {
        return "<restitch.Analysis " + std::to_string(a.analysis->principal.size()) + " principal offset(s)>";
      });

  m.def("analyze", [](const PyMesh& mesh, const std::string& descriptor, const std::string& matcher,
                      const std::string& detector, int threads) {
    Result<Analysis> a = error(StatusCode::internal, "not run");
    {
      py::gil_scoped_release release;
      a = analyze_named(*mesh.mesh, descriptor, matcher, detector, Progress(), threads);
    }
    return PyAnalysis{mesh.mesh, std::make_shared<const Analysis>(value(std::move(a)))};
  }, py::arg("mesh"), py::arg("descriptor") = "shot", py::arg("matcher") = "brute_force",
        py::arg("detector") = "histogram", py::arg("threads") = 0,
        "Finds how the mesh repeats. threads: 0 every core, 1 the calling thread. The GIL is released.");

  py::class_<PyResult>(m, "Result", "One resize.")
      .def_readonly("mesh", &PyResult::mesh)
      .def_readonly("report", &PyResult::report, "The fields of `restitch resize --json`.")
      .def_property_readonly("warnings", [](const PyResult& r) { return r.report["warnings"]; },
                             "What the result check flagged: [{'check': ..., 'message': ...}]; [] on a clean result.")
      .def_property_readonly("steps", [](const PyResult& r) { return r.report["steps_principal"]; },
                             "The whole repeats added along each principal offset.");

  py::class_<PyRetargeter>(m, "Retargeter", "Resizes one analysed mesh, keeping its caches between requests.")
      .def(py::init<const PyMesh&, const PyAnalysis&, const std::string&, const std::string&, const std::string&, bool>(),
           py::arg("mesh"), py::arg("analysis"), py::arg("label_space") = "lattice",
           py::arg("seam_energy") = "descriptor", py::arg("pivot") = "origin", py::arg("check") = true)
      .def("resize", &PyRetargeter::resize, py::arg("steps") = py::none(), py::arg("size") = py::none(),
           py::arg("exact") = false,
           "steps: whole repeats along each principal offset; or size: (x, y, z) model units, 0 keeps an axis, "
           "the nearest whole repeats (scaled about the pivot to the size with exact=True). The GIL is released.")
      .def("steps_for_size", &PyRetargeter::steps_for_size, py::arg("size"),
           "The steps along the principal offsets that come nearest to size.");
}
