// restitch/restitch.hpp - the umbrella header: everything, with the default policies.
//
// restitch resizes man-made 3D models the way a modeller would: it finds how
// the model repeats (restitch::analyze: offset statistics of matched
// descriptors, docs/method.md section 1), then rebuilds it longer, taller or
// shorter by stitching translated copies of itself along those repeats, with
// seams chosen by graph cut (restitch::Retargeter / restitch::retarget,
// sections 2 and 3).
//
//   #include <restitch/restitch.hpp>          // the algorithms
//   #define RESTITCH_GLTF_IMPLEMENTATION      // in exactly one .cpp of your program
//   #include <restitch/io/gltf.hpp>           // opt-in: glTF reading and writing
//
//   restitch::Result<restitch::Mesh> mesh = restitch::load_gltf("shelf.glb");
//   restitch::Result<restitch::Analysis> a = restitch::analyze(*mesh);
//   restitch::Result<restitch::RetargetResult> r = restitch::retarget(*mesh, *a, {2, 0, 0});
//   restitch::save_gltf(r->mesh, "longer.glb");
//
// Every stage is a policy (a template parameter with a default) that a custom
// build may replace: descriptor (ShotDescriptor, FpfhDescriptor), matcher
// (BruteForceMatcher, ReducedMatcher), offset detector
// (HistogramOffsetDetector, AutocorrelationOffsetDetector), label space (LatticeLabels, RegularLabels),
// max-flow back end (PushRelabelMaxFlow, the default; BkMaxFlow), graph solver (AlphaExpansion) and stitcher
// (ClipStitcher). Each contract is documented in its header and checked by a
// static_assert at the entry point. No call throws; each returns a Status or
// a Result.
//
// Opt-in headers, not included here because they bring heavy dependencies or
// code most programs do not need: restitch/io/gltf.hpp (glTF I/O, tinygltf),
// restitch/io/json_report.hpp (JSON reports, nlohmann::json),
// restitch/families/families.hpp (the generated sample families with exact
// ground truth), restitch/descriptor/xyzn.hpp (point files),
// restitch/solver/mrf_io.hpp (labelling-problem files) and
// restitch/runtime.hpp (the shipped policies chosen by name at run time: it
// instantiates every combination it can name, which a program that names
// its policies in code does not need).
//
// Compile cost: every function body here is a template (most with a defaulted
// `class = void` parameter), so a unit pays only for what it calls. Programs
// with many units can link the compiled mode (restitch/instantiate.hpp, CMake
// target restitch::compiled): the default policies are instantiated once and
// the other units see `extern template` declarations.
#pragma once

#include "restitch/analyze.hpp"
#include "restitch/descriptor/fpfh.hpp"
#include "restitch/descriptor/shot.hpp"
#include "restitch/energy/seam_energy.hpp"
#include "restitch/lattice/label_space.hpp"
#include "restitch/matcher/brute_force.hpp"
#include "restitch/matcher/reduced.hpp"
#include "restitch/mesh.hpp"
#include "restitch/mesh_boundary.hpp"
#include "restitch/offsets/autocorrelation.hpp"
#include "restitch/placement.hpp"
#include "restitch/retarget.hpp"
#include "restitch/solver/alpha_expansion.hpp"
#include "restitch/solver/max_flow_bk.hpp"
#include "restitch/solver/max_flow_push_relabel.hpp"
#include "restitch/solver/mrf.hpp"
#include "restitch/stitch/stitch.hpp"
