// restitch/detail/cell_hash.hpp - the one hashed grid: integer cells (x, y, z) to values, and points chained by cell.
//
// Several stages bucket things by a 3-D integer cell: Poisson-disk sampling
// (accepted samples), the offset histogram (bins), offset snapping (mesh
// vertices) and the stitcher's welding (seam vertices). They all use these:
//
//   Cell           three signed 64-bit cell coordinates (any range).
//   CellHashMap<V> open addressing with linear probing over the full key
//                  (no packing, so no range limit), grown at load 1/2; `find`
//                  gives a pointer to the value or null, `get` inserts.
//   CellChains     items (0, 1, 2, ...) chained per cell through one `next`
//                  array: `insert(cell, item)`, `for_each(cell, f)` visits the
//                  items of a cell, the most recently inserted first.
//
// What a caller computes from these must not depend on the visiting order:
// it is a hash order. Deterministic all the same (no randomness, no
// addresses). Cost O(1) expected per call; memory 2 slots per stored cell at
// most, plus one int32 per chained item.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace restitch::detail {

using Cell = std::array<std::int64_t, 3>;

/// The cell index floor(x / h) of a coordinate, saturated at +-2^62 so that any finite coordinate
/// (an unused vertex may lie anywhere) and its neighbours +-1 are representable (no overflow).
template <class = void>
std::int64_t cell_index(double x, double h) {
  return std::int64_t(std::clamp(std::floor(x / h), -4611686018427387904.0, 4611686018427387904.0));
}

template <class = void>
std::size_t hash_cell(const Cell& c) {
  std::uint64_t h = std::uint64_t(c[0]) * 0x9E3779B97F4A7C15ull;
  h = (h ^ (h >> 29)) + std::uint64_t(c[1]) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 31)) + std::uint64_t(c[2]) * 0x94D049BB133111EBull;
  return std::size_t(h ^ (h >> 32));
}

template <class V>
class CellHashMap {
 public:
  /// `expected`: how many cells will be stored (a size hint).
  explicit CellHashMap(std::size_t expected = 0) {
    std::size_t cap = 64;
    while (cap < 2 * expected + 2) cap *= 2;
    slots_.resize(cap);
  }

  std::size_t size() const { return used_; }

  /// The value of cell c, or null when c holds nothing.
  const V* find(const Cell& c) const {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = hash_cell(c) & mask;; i = (i + 1) & mask) {
      const Slot& s = slots_[i];
      if (!s.used) return nullptr;
      if (s.cell == c) return &s.value;
    }
  }

  /// The value of cell c, inserted as `initial` when c holds nothing; second: whether it was inserted.
  std::pair<V*, bool> get(const Cell& c, const V& initial = V()) {
    if (2 * (used_ + 1) > slots_.size()) grow();
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = hash_cell(c) & mask;; i = (i + 1) & mask) {
      Slot& s = slots_[i];
      if (s.used && s.cell == c) return {&s.value, false};
      if (!s.used) {
        s.used = true;
        s.cell = c;
        s.value = initial;
        ++used_;
        return {&s.value, true};
      }
    }
  }

 private:
  struct Slot {
    Cell cell{};
    V value{};
    bool used = false;
  };
  void grow() {
    std::vector<Slot> old(slots_.size() * 2);
    old.swap(slots_);
    const std::size_t mask = slots_.size() - 1;
    for (const Slot& s : old) {
      if (!s.used) continue;
      std::size_t i = hash_cell(s.cell) & mask;
      while (slots_[i].used) i = (i + 1) & mask;
      slots_[i] = s;
    }
  }

  std::vector<Slot> slots_;
  std::size_t used_ = 0;
};

class CellChains {
 public:
  /// `expected`: how many items will be inserted (a size hint).
  explicit CellChains(std::size_t expected = 0) : heads_(expected) { next_.reserve(expected); }

  /// Chains item `item` (the next item number: 0, 1, 2, ... in order) into cell c.
  template <class = void>
  void insert(const Cell& c, std::int32_t item) {
    std::int32_t& head = *heads_.get(c, -1).first;
    if (next_.size() <= std::size_t(item)) next_.resize(std::size_t(item) + 1, -1);
    next_[std::size_t(item)] = head;
    head = item;
  }

  /// Calls f(item) for every item of cell c.
  template <class F>
  void for_each(const Cell& c, F&& f) const {
    const std::int32_t* head = heads_.find(c);
    if (!head) return;
    for (std::int32_t i = *head; i >= 0; i = next_[std::size_t(i)]) f(i);
  }

  /// Calls f(item) for every item of the cells lo .. hi (inclusive, per axis), z outermost, x innermost.
  template <class F>
  void for_each_in(const Cell& lo, const Cell& hi, F&& f) const {
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x) for_each(Cell{x, y, z}, f);
  }

  /// Like for_each, but stops at the first item for which f returns true; returns whether one did.
  template <class F>
  bool any_of(const Cell& c, F&& f) const {
    const std::int32_t* head = heads_.find(c);
    if (!head) return false;
    for (std::int32_t i = *head; i >= 0; i = next_[std::size_t(i)])
      if (f(i)) return true;
    return false;
  }

 private:
  CellHashMap<std::int32_t> heads_;
  std::vector<std::int32_t> next_;
};

}  // namespace restitch::detail
