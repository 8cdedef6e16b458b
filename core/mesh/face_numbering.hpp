#pragma once
// Global numbering of the faces (facets) of a 3D mesh, each shared face once,
// in the order the cells first use them (cell_faces() order within a cell).
// A face is identified by its vertex set, so the numbering needs no
// orientation: Q2 hexahedra have one node per face, its centre.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/mesh/mesh.hpp"

namespace warpfem {

class FaceNumbering {
 public:
  explicit FaceNumbering(const Mesh<3>& mesh);

  Index num_faces() const { return static_cast<Index>(face_vertices_.size()); }
  /// Face id of local face `f` (cell_faces order) of `cell`.
  Index cell_face(Index cell, int f) const { return cell_face_(cell, f); }
  /// Face id of the face with these vertices (any order; 3 or 4 of them); -1 if there is none.
  Index find(const TableIndex* vertices, int count) const;
  /// Sorted vertices of a face (the last is -1 for a triangle).
  const std::array<Index, 4>& vertices(Index face) const {
    return face_vertices_[static_cast<std::size_t>(face)];
  }

 private:
  // Faces grouped by their smallest vertex, as in EdgeNumbering: for vertex a,
  // the faces whose smallest vertex is a are slot_face_[slot_start_[a] .. slot_end_[a]).
  std::vector<std::int32_t> slot_start_, slot_end_;
  std::unique_ptr<std::int32_t[]> slot_face_;
  std::vector<std::array<Index, 4>> face_vertices_;
  IndexTable cell_face_;
};

}  // namespace warpfem
