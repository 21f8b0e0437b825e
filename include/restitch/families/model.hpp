// restitch/families/model.hpp - what a generated family member is: parameters, catalogue entries, the model with its truth.
//
// See restitch/families/families.hpp for the contract of the generators.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "restitch/mesh.hpp"

namespace restitch {
namespace families {

/// One named numeric parameter of a sample, with its default and range.
struct Parameter {
  std::string name;
  double value = 0;  ///< the default
  double min = 0, max = 0;
  bool integer = false;  ///< counts and `detail`
  std::string help;
};

struct SampleInfo {
  std::string name;
  std::string description;
  std::string units;  ///< "m" or "mm": the unit of every length parameter and of the mesh
  std::vector<Parameter> parameters;
};

/// A part that occurs once along a generator (a key notch, a slot next to an end, a valve, a tall drawer):
/// the blocks it changes (module indices; -1 the start cap, modules[g] the end cap) and where a resize
/// keeps it ("low end", "high end" or "centre").
struct SamplePart {
  int generator = 0;
  int first = 0, last = 0;
  std::string anchor;
  std::string name;
};

/// A generated sample and its ground truth.
struct SampleModel {
  Mesh mesh;
  /// The true lattice generators in model units, in a fixed order
  /// (1 for fence and pin_header, 2 for the others).
  std::vector<Eigen::Vector3d> generators;
  /// For generator g, the count parameter that adding repeats along g increments.
  std::vector<std::string> count_parameters;
  /// Repeats along each generator: the value of count_parameters[g].
  std::vector<int> counts;
  /// Module blocks along each generator: counts[g] - 1 for the bookshelf
  /// (one compartment lives in the end cap, next to the side panel or the
  /// top board), counts[g] - 2 for the DIP (each end cap holds the end pins),
  /// counts[g] for the others.
  std::vector<int> modules;
  /// Corner of module 0 along every generator: module (i, j) is the template
  /// module translated by origin + i * generators[0] + j * generators[1].
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  /// Per generator, per face: -1 if the face belongs to the start cap along
  /// that generator, i in [0, modules[g]) for module i, modules[g] for the end cap.
  std::vector<Eigen::VectorXi> face_block;
  /// The parts that occur once (empty for the plain families, whose modules are all translates of module 0).
  std::vector<SamplePart> parts;
};

/// Largest mesh `generate` builds (triangles); larger requests get too_large.
inline constexpr std::uint64_t max_sample_triangles = 4000000;

}  // namespace families
}  // namespace restitch
