// restitch/retarget/report.hpp - what a resize returns: the mesh, the labels and the report (docs/method.md 2.8, 2.9).
//
// Plain types, filled by the Retargeter's stages (restitch/retarget.hpp).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "restitch/energy/seam_geometry.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/placement.hpp"
#include "restitch/lattice/structure.hpp"

namespace restitch {

/// One seam of an output: two neighbouring output cells (sharing a face) with different labels, or an
/// output cell on a resized end whose label differs from its anchor (cell_b is then the virtual cell
/// just outside the output grid, label_b the anchor; docs/method.md 2.3).
struct SeamReport {
  Eigen::Array3i cell_a = Eigen::Array3i::Zero(), cell_b = Eigen::Array3i::Zero();    ///< output cells
  Eigen::Array3i label_a = Eigen::Array3i::Zero(), label_b = Eigen::Array3i::Zero();  ///< their shifts d
  double mismatch = 0;  ///< model units: min of the slab mismatches on either side (docs/method.md 2.8)
  bool outer = false;   ///< cell_b lies outside the output (an anchored end)
  double offset = 0;    ///< inner seams: where the cut lies, in cells from the face of cell_a toward cell_b (2.9)
};

/// A part that occurs once (restitch/lattice/structure.hpp) as a resize kept it: its input slabs along its
/// lattice axis, its anchor, and the shift along that axis it was copied with (its slabs lie at slab + shift
/// in the output grid), and for a centred part moved alone by a further half period, which way.
struct PartReport {
  int axis = 0, first = 0, last = 0;
  PartAnchor anchor = PartAnchor::low;
  int shift = 0;
  /// +1 or -1: moved alone a further half period that way along its axis, so it stays centred where whole
  /// periods cannot keep it so (restitch/retarget/centring.hpp); 0 otherwise.
  int half = 0;
};

/// Something in a result a modeller would look at: the check that found it and a sentence. Checks:
/// "undecided axis", "short repeat", "part off centre", "pair" and "two copies" (known when the request is planned,
/// restitch/retarget/labelling.hpp), "open seam", "part count", "size", "floating piece" and "side by side" (the result check, restitch/retarget/check.hpp).
struct ResultWarning {
  std::string check;
  std::string message;
  /// Known when the request is planned (what whole periods cannot do, or a reading that may be wrong),
  /// rather than found in the result by its check.
  bool planned() const {
    return check == "undecided axis" || check == "short repeat" || check == "part off centre" || check == "pair" ||
           check == "two copies";
  }
};

struct RetargetReport {
  Eigen::Array3i steps = Eigen::Array3i::Zero();       ///< as requested, per lattice axis (dummies included; see lattice_steps_from_principal)
  Eigen::Array3i grid_steps = Eigen::Array3i::Zero();  ///< cells added per axis of the label grid
  Eigen::Array3i cells_in = Eigen::Array3i::Ones(), cells_out = Eigen::Array3i::Ones();
  int nodes = 0, labels = 0, edges = 0, cycles = 0;
  double energy = 0;
  bool non_metric = false;
  std::size_t triangles_in = 0, triangles_out = 0, vertices_out = 0, regions = 0;
  /// Boundary (open) edges of the input and of the output: positions welded over the whole mesh at the
  /// default weld tolerance (1e-6 of the bounding-box diagonal), attributes ignored, edges used by exactly
  /// one face (restitch/mesh_boundary.hpp). Counted by the result check (RetargetOptions::check, `checked`
  /// below; else 0).
  std::size_t boundary_edges_in = 0, boundary_edges_out = 0;
  /// The stitcher's weld tolerance as used, relative to the input's diagonal (0 for a stitcher without
  /// one), and whether it was measured from the copies (RetargetOptions::measure_weld_tolerance) rather
  /// than the stitcher's own or the one asked for.
  double weld_tolerance = 0;
  bool weld_tolerance_measured = false;
  Eigen::Vector3d size_in = Eigen::Vector3d::Zero(),
                  size_out = Eigen::Vector3d::Zero();  ///< bounding boxes, model units
  std::map<std::string, double> timings_ms;            ///< energy, solve, stitch, boundary (when counted), total (informative only)
  Placement placement;  ///< the pivot modes and point, and the translation applied (restitch/placement.hpp)
  /// retarget_to_size with exact: the scale applied per world axis about placement.pivot (1 = none), and
  /// the size of the nearest whole-repeat result before it.
  bool exact = false;
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  Eigen::Vector3d size_nearest = Eigen::Vector3d::Zero();
  /// The pairwise term solved, and every seam of the output measured on the geometry (model units).
  SeamEnergy seam_energy = SeamEnergy::descriptor;
  std::vector<SeamReport> seams;
  double max_seam_mismatch = 0;
  double seam_tolerance = 0;  ///< as used (RetargetOptions::seam_tolerance, or its default)
  double sample_spacing = 0;  ///< model units (CellSlabs::spacing)
  /// What a modeller should look at (see ResultWarning); empty when the result passed every check.
  std::vector<ResultWarning> warnings;
  /// Whether the result check ran (RetargetOptions::check), and the output's open edges that are no copy
  /// of the input's own, each as its two corners (output space).
  bool checked = false;
  std::vector<std::array<Eigen::Vector3f, 2>> open_edges;
  std::size_t boundary_edges_new() const { return open_edges.size(); }
  /// The parts that occur once along the resized axes, as kept (RetargetOptions::keep_parts).
  std::vector<PartReport> parts;
  /// Where the planes between output cells lie (docs/method.md 2.9): plane_offsets[a][i], i = 0 ..
  /// cells_out[a], in cells from cell plane i along lattice axis a (0: on it; within +-1/2). Empty when
  /// no plane moved; seams_moved counts the planes that did.
  std::array<std::vector<double>, 3> plane_offsets;
  int seams_moved = 0;

  /// The plane between output cells i - 1 and i along lattice axis a as it lies (canonical units of the
  /// output grid: i plus its offset).
  template <class = void>
  double plane(int a, int i) const {
    const std::vector<double>& o = plane_offsets[std::size_t(a)];
    return double(i) + (o.empty() ? 0.0 : o[std::size_t(i)]);
  }
  /// The output cell holding canonical point t of the output grid (clamped into it), with the planes as
  /// they lie.
  template <class = void>
  Eigen::Array3i cell_of(const Eigen::Vector3d& t) const {
    Eigen::Array3i x;
    for (int a = 0; a < 3; ++a) {
      int i = std::clamp(int(std::floor(t[a])), 0, cells_out[a] - 1);
      if (i + 1 < cells_out[a] && t[a] >= plane(a, i + 1)) ++i;  // offsets lie within half a cell
      else if (i > 0 && t[a] < plane(a, i)) --i;
      x[a] = i;
    }
    return x;
  }
};

struct RetargetResult {
  Mesh mesh;
  RetargetReport report;
  Lattice grid;                        ///< the grid the labels live on, as placed in the output (model units)
  std::vector<Eigen::Array3i> labels;  ///< the label shifts, by label index
  std::vector<int> cell_labels;        ///< label index per output cell (linear order)
  std::vector<int> face_labels;        ///< label index per output face (when requested)
};

}  // namespace restitch
