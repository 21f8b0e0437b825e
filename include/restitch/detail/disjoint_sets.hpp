// restitch/detail/disjoint_sets.hpp - union-find over 0 .. n-1, deterministic.
//
// Used to group the faces of a mesh into pieces (restitch/retarget/check.hpp) and samples into groups of
// one content (restitch/lattice/structure.hpp). Cost: near O(1) per call (path halving).
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace restitch::detail {

/// Disjoint sets over 0 .. n-1 (path halving, union by index: the lower root wins, so deterministic).
struct DisjointSets {
  std::vector<std::uint32_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace restitch::detail
