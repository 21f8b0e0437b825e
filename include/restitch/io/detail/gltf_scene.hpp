// restitch/io/detail/gltf_scene.hpp - the default scene's node tree walked into mesh instances.
//
// Part of restitch/io/gltf.hpp, which includes it after configuring and
// including tinygltf; do not include it on its own.
//
// `walk_scene` visits the default scene depth first (roots and children in
// file order) and lists every node that shows a mesh, with its world matrix
// (the product of the local matrices from the root down, in doubles). It
// decodes no geometry: the reader decodes each mesh once and places it per
// instance. Errors (no scene, a default scene or node or mesh index out of
// range, a node reached twice or deeper than 1024, a non-finite world
// matrix) stop the walk; the instances found before the error are kept, so
// the caller can handle them first and report the error where a single pass
// over the tree would have met it. Never throws.
//
// Cost: linear in the number of nodes.
#pragma once

#ifndef RESTITCH_GLTF_PARTS
#error "include restitch/io/gltf.hpp, not its detail parts"
#endif

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "restitch/status.hpp"

namespace restitch::detail {

// A node's local matrix: its `matrix`, else T * R * S.
template <class = void>
Eigen::Matrix4d node_local_matrix(const tinygltf::Node& n) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  if (n.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) M(r, c) = n.matrix[c * 4 + r];  // column-major
    return M;
  }
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity(), R = Eigen::Matrix4d::Identity(), S = Eigen::Matrix4d::Identity();
  if (n.translation.size() == 3)
    T.block<3, 1>(0, 3) = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
  if (n.rotation.size() == 4) {
    Eigen::Quaterniond q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    if (q.norm() > 0) q.normalize();
    R.block<3, 3>(0, 0) = q.toRotationMatrix();
  }
  if (n.scale.size() == 3) S.diagonal().head<3>() = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
  return T * R * S;
}

// One node showing one mesh.
struct MeshInstance {
  int node = -1;
  int mesh = -1;          // a valid index into Model::meshes
  Eigen::Matrix4d world;  // finite
};

// Appends the default scene's mesh instances, in depth-first order, to
// `instances`; on error, those found before it stay there.
template <class = void>
Status walk_scene(const tinygltf::Model& model, std::vector<MeshInstance>& instances) {
  if (model.scenes.empty()) return error(StatusCode::invalid_mesh, "the file has no scene, so nothing to resize");
  const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene >= int(model.scenes.size()))
    return error(StatusCode::parse_error, "the default scene index is out of range");
  const std::vector<int>& roots = model.scenes[scene].nodes;

  // Depth-first traversal with world matrices; a cycle or a bad index is an error.
  struct Item {
    int node;
    Eigen::Matrix4d world;
    int depth;
  };
  std::vector<Item> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, Eigen::Matrix4d::Identity(), 0});
  std::vector<int> visits(model.nodes.size(), 0);
  while (!stack.empty()) {
    Item item = stack.back();
    stack.pop_back();
    if (item.node < 0 || item.node >= int(model.nodes.size()))
      return error(StatusCode::parse_error,
                   "the scene refers to node " + std::to_string(item.node) + ", which does not exist");
    if (++visits[item.node] > 1 || item.depth > 1024)
      return error(StatusCode::parse_error,
                   "node " + std::to_string(item.node) + " is reached twice: the node hierarchy is not a tree");
    const tinygltf::Node& node = model.nodes[item.node];
    const Eigen::Matrix4d world = item.world * node_local_matrix(node);
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world, item.depth + 1});
    if (node.mesh < 0) continue;
    if (node.mesh >= int(model.meshes.size()))
      return error(StatusCode::parse_error, "node " + std::to_string(item.node) + " refers to mesh " +
                                                std::to_string(node.mesh) + ", which does not exist");
    if (!world.allFinite())
      return error(StatusCode::invalid_mesh, "node " + std::to_string(item.node) + " has a non-finite transform");
    instances.push_back({item.node, node.mesh, world});
  }
  return {};
}

}  // namespace restitch::detail
