#pragma once
// The face groups of a Wavefront OBJ surface ("g name" lines), which CGAL's
// OBJ reader skips. Faces are counted the way CGAL reads them (one polygon per
// "f" line, in file order), so the groups line up with Polyhedron::read's triangles.

#include <string>
#include <vector>

namespace warpfem {

struct ObjFaceGroups {
  std::vector<int> face_group;     ///< group of each face, in file order
  std::vector<std::string> names;  ///< per group; group k is the k-th name that has faces
};

/// Reads the "g" statements of an OBJ file: faces before any "g" (or after a
/// bare "g") are in group "default"; a face's group is the first name of its
/// "g" line. Throws warpfem::Error naming the file when it cannot be read.
ObjFaceGroups read_obj_face_groups(const std::string& path);

}  // namespace warpfem
