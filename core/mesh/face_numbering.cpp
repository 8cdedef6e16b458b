#include "core/mesh/face_numbering.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace warpfem {

namespace {
/// The vertex set of a face as a sorted key, padded with -1 (triangles).
std::array<Index, 4> face_key(const TableIndex* vertices, int count) {
  std::array<Index, 4> key{-1, -1, -1, -1};
  for (int k = 0; k < count; ++k) {  // insertion sort of at most four entries
    int j = k;
    for (; j > 0 && key[static_cast<std::size_t>(j - 1)] > vertices[k]; --j)
      key[static_cast<std::size_t>(j)] = key[static_cast<std::size_t>(j - 1)];
    key[static_cast<std::size_t>(j)] = vertices[k];
  }
  return key;
}
}  // namespace

FaceNumbering::FaceNumbering(const Mesh<3>& mesh) {
  mesh.require_whole("FaceNumbering");
  const auto& faces = cell_faces(mesh.cell_type);
  const Index nc = mesh.num_cells(), nv = mesh.num_vertices(), nf = static_cast<Index>(faces.size());
  require(nv < std::numeric_limits<std::int32_t>::max() && nc * nf < std::numeric_limits<std::int32_t>::max(),
          "FaceNumbering: more than 2^31 vertices or cell faces");
  cell_face_.resize(nc, nf);
  const auto local_key = [&](Index c, Index f) {
    TableIndex v[4];
    const auto& face = faces[static_cast<std::size_t>(f)];
    for (std::size_t k = 0; k < face.size(); ++k) v[k] = mesh.cells(c, face[k]);
    return face_key(v, static_cast<int>(face.size()));
  };
  // 1. Every cell face reserves a slot with its smallest vertex (an upper bound
  // on the faces starting there).
  slot_start_.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (Index c = 0; c < nc; ++c)
    for (Index f = 0; f < nf; ++f) ++slot_start_[static_cast<std::size_t>(local_key(c, f)[0]) + 1];
  for (Index v = 0; v < nv; ++v) slot_start_[v + 1] += slot_start_[v];
  slot_face_ = std::make_unique_for_overwrite<std::int32_t[]>(static_cast<std::size_t>(slot_start_[nv]));
  slot_end_.assign(slot_start_.begin(), slot_start_.end() - 1);
  // 2. One pass over the cells in order: a face is numbered when a cell first uses it.
  for (Index c = 0; c < nc; ++c)
    for (Index f = 0; f < nf; ++f) {
      const std::array<Index, 4> key = local_key(c, f);
      const Index a = key[0];
      Index id = -1;
      for (Index m = slot_start_[a]; m < slot_end_[a] && id < 0; ++m)
        if (face_vertices_[static_cast<std::size_t>(slot_face_[m])] == key) id = slot_face_[m];
      if (id < 0) {
        id = static_cast<Index>(face_vertices_.size());
        face_vertices_.push_back(key);
        slot_face_[slot_end_[a]++] = static_cast<std::int32_t>(id);
      }
      cell_face_(c, f) = static_cast<TableIndex>(id);
    }
}

Index FaceNumbering::find(const TableIndex* vertices, int count) const {
  require(count == 3 || count == 4,
          "FaceNumbering::find: a face has 3 or 4 vertices, not " + std::to_string(count));
  const std::array<Index, 4> key = face_key(vertices, count);
  const Index a = key[0];
  if (a < 0 || a >= static_cast<Index>(slot_end_.size())) return -1;
  for (Index m = slot_start_[a]; m < slot_end_[a]; ++m)
    if (face_vertices_[static_cast<std::size_t>(slot_face_[m])] == key) return slot_face_[m];
  return -1;
}

}  // namespace warpfem
