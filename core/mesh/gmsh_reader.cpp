#include "core/mesh/gmsh_reader.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/structured_mesher.hpp"

namespace warpfem {
namespace {

class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_)
      throw Error("cannot open mesh file", {.file = path, .key_path = "mesh.file", .hint = "check the path"});
  }
  bool next(std::string& line) {
    while (std::getline(in_, line)) {
      ++number_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty()) return true;
    }
    return false;
  }
  std::istringstream next_stream(const char* what) {
    std::string line;
    if (!next(line)) fail(std::string("unexpected end of file while reading ") + what);
    return std::istringstream(line);
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw Error("line " + std::to_string(number_) + ": " + message,
                {.file = path_,
                 .key_path = "",
                 .hint = "write the mesh as Gmsh ASCII format 2.2 or 4.1 (gmsh -format msh22)"});
  }
  void expect(const std::string& tag) {
    std::string line;
    if (!next(line) || line != tag) fail("expected " + tag);
  }
  int line_number() const { return number_; }

 private:
  std::string path_;
  std::ifstream in_;
  int number_ = 0;
};

/// Corners of the first-order Gmsh element types warpfem reads; 0 for others.
int nodes_of_type(long type) {
  switch (type) {
    case 2: return 3;   // 3-node triangle
    case 3: return 4;   // 4-node quadrangle
    case 4: return 4;   // 4-node tetrahedron
    case 5: return 8;   // 8-node hexahedron (VTK corner order)
    default: return 0;  // anything else is skipped (or refused where it would matter)
  }
}

/// Dimension of the Gmsh element types of format 2.2, which has no entity dimension.
int dimension_of_type(long type) {
  switch (type) {
    case 15: return 0;
    case 1:
    case 8:
    case 26:
    case 27:
    case 28: return 1;
    case 2:
    case 3:
    case 9:
    case 10:
    case 16:
    case 20:
    case 21:
    case 22:
    case 23:
    case 24:
    case 25: return 2;
    case 4:
    case 5:
    case 6:
    case 7:
    case 11:
    case 12:
    case 13:
    case 14:
    case 17:
    case 18:
    case 19:
    case 29:
    case 30:
    case 31:
    case 92:
    case 93: return 3;
    default: return -1;
  }
}

struct GmshElement {
  long id = 0;
  int dim = 0;
  long type = 0;
  int physical = 0;  ///< 0: in no physical group
  int line = 0;
  std::vector<long> nodes;
};

/// The parts of a Gmsh file warpfem uses: every node, the elements of the
/// types it reads (plus the first element of a 3D type it cannot read) and
/// the names of physical groups.
struct GmshFile {
  std::unordered_map<long, Index> node_index;
  std::vector<Point<3>> nodes;
  std::vector<GmshElement> elements;
  std::optional<GmshElement> unsupported_3d;
  std::map<std::pair<int, int>, std::string> physical_names;  ///< (dim, tag) -> name
};

/// A count from the file: non-negative, else the line is refused.
long read_count(LineReader& r, std::istringstream& in, const char* what) {
  long n = -1;
  if (!(in >> n) || n < 0)
    r.fail(std::string("expected the number of ") + what + " (a non-negative integer)");
  return n;
}

GmshFile parse(LineReader& r) {
  r.expect("$MeshFormat");
  double version = 0;
  int file_type = 0;
  r.next_stream("the format line") >> version >> file_type;
  if (file_type != 0) r.fail("binary .msh files are not supported");
  if (version < 2.0 || version >= 5.0) r.fail("unsupported format version " + std::to_string(version));
  const bool v4 = version >= 4.0;
  r.expect("$EndMeshFormat");

  GmshFile file;
  std::map<std::pair<int, long>, int> entity_physical;  // format 4.1: (dim, entity) -> physical tag
  const auto add_node = [&](long tag, double x, double y, double z) {
    if (!file.node_index.emplace(tag, static_cast<Index>(file.nodes.size())).second)
      r.fail("node " + std::to_string(tag) + " is defined twice");
    file.nodes.emplace_back(x, y, z);
  };
  const auto add_element = [&](long id, int dim, long type, int physical, std::istringstream& in) {
    const int n = nodes_of_type(type);
    if (n == 0) {
      if (dim == 3 && !file.unsupported_3d)
        file.unsupported_3d = GmshElement{id, dim, type, 0, r.line_number(), {}};
      return;
    }
    GmshElement e{id, dim, type, physical, r.line_number(), std::vector<long>(static_cast<std::size_t>(n))};
    for (auto& v : e.nodes)
      if (!(in >> v)) r.fail("too few node ids for the element");
    file.elements.push_back(std::move(e));
  };
  std::string line;
  while (r.next(line)) {
    if (line == "$Nodes") {
      auto head = r.next_stream("the node count");
      if (v4) {
        const long blocks = read_count(r, head, "node blocks"), count = read_count(r, head, "nodes");
        long read = 0;
        for (long b = 0; b < blocks; ++b) {
          long dim, tag, parametric;
          auto block = r.next_stream("a node block");
          if (!(block >> dim >> tag >> parametric))
            r.fail("expected \"dim tag parametric count\" of a node block");
          const long n = read_count(r, block, "nodes in the block");
          // Grown line by line: a count the file does not back up allocates nothing.
          std::vector<long> tags;
          for (long i = 0; i < n; ++i)
            if (!(r.next_stream("a node tag") >> tags.emplace_back())) r.fail("expected a node tag");
          for (long i = 0; i < n; ++i) {
            double x, y, z;
            if (!(r.next_stream("node coordinates") >> x >> y >> z))
              r.fail("expected three node coordinates");
            add_node(tags[static_cast<std::size_t>(i)], x, y, z);
          }
          read += n;
        }
        if (read != count)
          r.fail("the $Nodes header announces " + std::to_string(count) + " nodes, the blocks hold " +
                 std::to_string(read));
      } else {
        const long count = read_count(r, head, "nodes");
        for (long i = 0; i < count; ++i) {
          long id;
          double x, y, z;
          if (!(r.next_stream("a node") >> id >> x >> y >> z)) r.fail("expected \"id x y z\"");
          add_node(id, x, y, z);
        }
      }
      r.expect("$EndNodes");
    } else if (line == "$Elements") {
      auto head = r.next_stream("the element count");
      if (v4) {
        const long blocks = read_count(r, head, "element blocks"), count = read_count(r, head, "elements");
        long read = 0;
        for (long b = 0; b < blocks; ++b) {
          long dim, tag, type;
          auto block = r.next_stream("an element block");
          if (!(block >> dim >> tag >> type)) r.fail("expected \"dim tag type count\" of an element block");
          const long n = read_count(r, block, "elements in the block");
          const auto physical = entity_physical.find({static_cast<int>(dim), tag});
          for (long i = 0; i < n; ++i) {
            auto in = r.next_stream("an element");
            long id;
            if (!(in >> id)) r.fail("expected an element id");
            add_element(id, static_cast<int>(dim), type,
                        physical == entity_physical.end() ? 0 : physical->second, in);
          }
          read += n;
        }
        if (read != count)
          r.fail("the $Elements header announces " + std::to_string(count) + " elements, the blocks hold " +
                 std::to_string(read));
      } else {
        const long count = read_count(r, head, "elements");
        for (long i = 0; i < count; ++i) {
          auto in = r.next_stream("an element");
          long id, type;
          if (!(in >> id >> type)) r.fail("expected \"id type tag-count tags... node-ids...\"");
          const long ntags = read_count(r, in, "tags");
          // Each tag must be on the line (a huge tag count must not loop on a failed stream).
          long t = 0, physical = 0;
          for (long k = 0; k < ntags; ++k) {
            if (!(in >> t)) r.fail("fewer tags than the element's tag count");
            if (k == 0) physical = t;  // the first tag is the physical group
          }
          add_element(id, dimension_of_type(type), type, static_cast<int>(std::clamp(physical, 0L, 1L << 30)),
                      in);
        }
      }
      r.expect("$EndElements");
    } else if (line == "$Entities" && v4) {
      // Points carry no bounding box; curves, surfaces and volumes do.
      auto head = r.next_stream("the entity counts");
      long count[4];
      for (long& c : count) c = read_count(r, head, "entities");
      for (int dim = 0; dim < 4; ++dim)
        for (long i = 0; i < count[dim]; ++i) {
          auto in = r.next_stream("an entity");
          long tag;
          double box;
          if (!(in >> tag)) r.fail("expected an entity tag");
          for (int k = 0; k < (dim == 0 ? 3 : 6); ++k)
            if (!(in >> box)) r.fail("expected the entity's coordinates");
          const long n = read_count(r, in, "physical tags of the entity");
          long physical = 0;
          // A boundary surface names one part; points and curves may be in several groups.
          if (n > 1 && dim == 2)
            r.fail("surface " + std::to_string(tag) + " belongs to " + std::to_string(n) +
                   " physical groups; put it in one");
          if (n >= 1 && (!(in >> physical) || physical == 0)) r.fail("expected a non-zero physical tag");
          if (n >= 1)
            entity_physical[{dim, tag}] = static_cast<int>(std::clamp(std::abs(physical), 1L, 1L << 30));
        }
      r.expect("$EndEntities");
    } else if (line == "$PhysicalNames") {
      auto head = r.next_stream("the number of physical names");
      const long count = read_count(r, head, "physical names");
      for (long i = 0; i < count; ++i) {
        auto in = r.next_stream("a physical name");
        int dim, tag;
        std::string name;
        if (!(in >> dim >> tag) || !std::getline(in >> std::ws, name))
          r.fail("expected \"dim tag \\\"name\\\"\"");
        if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
          name = name.substr(1, name.size() - 2);
        file.physical_names[{dim, tag}] = name;
      }
      r.expect("$EndPhysicalNames");
    } else if (!line.empty() && line[0] == '$') {
      // Skip sections we do not use ($Periodic, $NodeData, ...).
      const std::string end = "$End" + line.substr(1);
      while (r.next(line) && line != end) {
      }
    }
  }
  return file;
}

std::string point_text(const Point<3>& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

Error mesh_error(const std::string& path, const std::string& message, const std::string& hint) {
  return Error(message, {.file = path, .key_path = "mesh.file", .hint = hint});
}

/// det of the Jacobian of a trilinear hexahedron (VTK corner order) at (u, v, w) in [0, 1]^3.
double hex_det(const std::array<Point<3>, 8>& x, double u, double v, double w) {
  static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  const double t[3] = {u, v, w};
  for (int k = 0; k < 8; ++k)
    for (int d = 0; d < 3; ++d) {
      double g = 1;  // ∂/∂t_d of the tensor-product hat function of corner k
      for (int e = 0; e < 3; ++e) {
        const double s = corner[k][e] ? 1.0 : -1.0;
        g *= e == d ? s : (corner[k][e] ? t[e] : 1 - t[e]);
      }
      J.col(d) += g * x[static_cast<std::size_t>(k)];
    }
  return J.determinant();
}

}  // namespace

Mesh<2> read_gmsh(const std::string& path, const Polygon& source) {
  LineReader r(path);
  const GmshFile file = parse(r);
  // Format 4.1 gives each element its entity's dimension: only 2D entities are
  // cells (a 3D file's boundary triangles then mix in too in format 2.2).
  int cell_nodes = 0;
  std::vector<const GmshElement*> cells;
  for (const GmshElement& e : file.elements) {
    if (e.dim != 2 || (e.type != 2 && e.type != 3)) continue;
    const int n = nodes_of_type(e.type);
    if (cell_nodes != 0 && cell_nodes != n) r.fail("mixed triangles and quadrilaterals are not supported");
    cell_nodes = n;
    cells.push_back(&e);
  }
  if (cells.empty()) r.fail("no triangles or quadrilaterals found");

  Mesh<2> m;
  m.cell_type = cell_nodes == 3 ? CellType::triangle : CellType::quadrilateral;
  // Keep only nodes used by cells (Gmsh also stores geometry points).
  std::unordered_map<long, Index> used;
  std::vector<Point<2>> verts;
  m.cells.resize(static_cast<Index>(cells.size()), cell_nodes);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (int k = 0; k < cell_nodes; ++k) {
      const long tag = cells[c]->nodes[static_cast<std::size_t>(k)];
      auto it = file.node_index.find(tag);
      if (it == file.node_index.end()) r.fail("element refers to unknown node " + std::to_string(tag));
      auto [u, inserted] = used.try_emplace(tag, static_cast<Index>(verts.size()));
      if (inserted) verts.push_back(file.nodes[static_cast<std::size_t>(it->second)].head<2>());
      m.cells(static_cast<Index>(c), k) = u->second;
    }
  }
  m.vertices.resize(static_cast<Index>(verts.size()), 2);
  for (std::size_t i = 0; i < verts.size(); ++i) m.vertices.row(static_cast<Index>(i)) = verts[i].transpose();
  // Orient every cell counter-clockwise and check the covered area.
  double area = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    double a = 0;
    for (int k = 0; k < cell_nodes; ++k) {
      const Point<2> p = m.vertex(m.cells(c, k)), q = m.vertex(m.cells(c, (k + 1) % cell_nodes));
      a += p.x() * q.y() - q.x() * p.y();
    }
    if (a < 0) m.cells.row(c) = m.cells.row(c).reverse().eval();
    area += 0.5 * std::abs(a);
  }
  if (std::abs(area - source.signed_area()) > 1e-8 * source.signed_area())
    throw mesh_error(path,
                     "the mesh covers area " + std::to_string(area) + " but the source polygon has area " +
                         std::to_string(source.signed_area()),
                     "mesh exactly the source polygon of map.source");
  m.boundary_facets = find_boundary_facets(m);
  try {
    tag_boundary_facets(m, source);
  } catch (const Error& e) {
    throw mesh_error(path, e.message(), e.context().hint);
  }
  return m;
}

GmshVolumeMesh read_gmsh(const std::string& path, const Polyhedron& source) {
  LineReader r(path);
  const GmshFile file = parse(r);
  if (file.unsupported_3d)
    throw mesh_error(path,
                     "line " + std::to_string(file.unsupported_3d->line) + ": element " +
                         std::to_string(file.unsupported_3d->id) + " has Gmsh type " +
                         std::to_string(file.unsupported_3d->type) +
                         ", a 3D element warpfem does not read (it reads 4-node tetrahedra, type 4, and "
                         "8-node hexahedra, type 5)",
                     "mesh the volume with first-order tetrahedra or hexahedra only (gmsh -3 -order 1)");
  int cell_nodes = 0;
  std::vector<const GmshElement*> cells, facets;
  for (const GmshElement& e : file.elements) {
    if (e.dim == 3 && (e.type == 4 || e.type == 5)) {
      const int n = nodes_of_type(e.type);
      if (cell_nodes != 0 && cell_nodes != n)
        throw mesh_error(path,
                         "line " + std::to_string(e.line) + ": element " + std::to_string(e.id) +
                             " mixes hexahedra with tetrahedra",
                         "mesh the volume with one cell type");
      cell_nodes = n;
      cells.push_back(&e);
    } else if (e.dim == 2 && (e.type == 2 || e.type == 3) && e.physical != 0) {
      facets.push_back(&e);
    }
  }
  if (cells.empty())
    throw mesh_error(path, "no tetrahedra or hexahedra found",
                     "mesh the volume (gmsh -3) and save its 3D elements (type 4 or 5)");

  GmshVolumeMesh out;
  Mesh<3>& m = out.mesh;
  m.cell_type = cell_nodes == 4 ? CellType::tetrahedron : CellType::hexahedron;
  std::unordered_map<long, Index> used;
  std::vector<long> tag_of_vertex;
  std::vector<Point<3>> verts;
  m.cells.resize(static_cast<Index>(cells.size()), cell_nodes);
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (int k = 0; k < cell_nodes; ++k) {
      const long tag = cells[c]->nodes[static_cast<std::size_t>(k)];
      const auto it = file.node_index.find(tag);
      if (it == file.node_index.end())
        throw mesh_error(path,
                         "line " + std::to_string(cells[c]->line) + ": element " +
                             std::to_string(cells[c]->id) + " refers to node " + std::to_string(tag) +
                             ", which $Nodes does not define",
                         "save the whole mesh (all nodes) from Gmsh");
      const auto [u, inserted] = used.try_emplace(tag, static_cast<Index>(verts.size()));
      if (inserted) {
        verts.push_back(file.nodes[static_cast<std::size_t>(it->second)]);
        tag_of_vertex.push_back(tag);
      }
      m.cells(static_cast<Index>(c), k) = u->second;
    }
  m.vertices.resize(static_cast<Index>(verts.size()), 3);
  for (std::size_t i = 0; i < verts.size(); ++i) m.vertices.row(static_cast<Index>(i)) = verts[i].transpose();

  // Orient every cell positively and add up the volume.
  const double diameter = (source.bbox_max() - source.bbox_min()).norm();
  const double degenerate = 1e-12 * diameter * diameter * diameter;
  double volume = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    const GmshElement& e = *cells[static_cast<std::size_t>(c)];
    const auto refuse = [&](const std::string& what) {
      return mesh_error(path,
                        "line " + std::to_string(e.line) + ": element " + std::to_string(e.id) + " " + what,
                        "repair the mesh in Gmsh (every cell must have positive volume)");
    };
    if (m.cell_type == CellType::tetrahedron) {
      const Point<3> a = m.vertex(m.cells(c, 0));
      const double det =
          (m.vertex(m.cells(c, 1)) - a).cross(m.vertex(m.cells(c, 2)) - a).dot(m.vertex(m.cells(c, 3)) - a);
      if (!(std::abs(det) > degenerate))
        throw refuse("is a degenerate tetrahedron (volume " + std::to_string(det / 6) + ")");
      if (det < 0) std::swap(m.cells(c, 1), m.cells(c, 2));
      volume += std::abs(det) / 6;
    } else {
      std::array<Point<3>, 8> x;
      for (int k = 0; k < 8; ++k) x[static_cast<std::size_t>(k)] = m.vertex(m.cells(c, k));
      int positive = 0, negative = 0;
      for (int k = 0; k < 8; ++k) {
        const double det = hex_det(x, k & 1, (k >> 1) & 1, k >> 2);
        positive += det > degenerate;
        negative += det < -degenerate;
      }
      if (positive != 8 && negative != 8)
        throw refuse(
            "is a twisted or degenerate hexahedron (its Jacobian changes sign or vanishes at a corner)");
      if (negative == 8) {  // mirrored: swap the two ends of the corner loops
        std::swap(m.cells(c, 1), m.cells(c, 3));
        std::swap(m.cells(c, 5), m.cells(c, 7));
        for (int k : {1, 5}) std::swap(x[static_cast<std::size_t>(k)], x[static_cast<std::size_t>(k + 2)]);
      }
      // 2 x 2 x 2 Gauss points integrate the (degree 2 per variable) Jacobian exactly.
      const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
      for (int k = 0; k < 8; ++k) volume += hex_det(x, g[k & 1], g[(k >> 1) & 1], g[k >> 2]) / 8;
    }
  }
  const double expected = source.signed_volume();
  if (!(std::abs(volume - expected) <= 1e-8 * expected))
    throw mesh_error(path,
                     "the mesh has volume " + std::to_string(volume) + " but " + source.name() +
                         " has volume " + std::to_string(expected),
                     "mesh exactly the source polyhedron of map.source (the same surface, the same units)");

  // Every vertex of the source is a mesh vertex (the map and the boundary parts meet there).
  {
    std::vector<Index> by_x(verts.size());
    for (std::size_t i = 0; i < by_x.size(); ++i) by_x[i] = static_cast<Index>(i);
    std::sort(by_x.begin(), by_x.end(),
              [&](Index a, Index b) { return m.vertices(a, 0) < m.vertices(b, 0); });
    const double tolerance = 1e-9 * diameter;
    for (Index v = 0; v < source.vertex_count(); ++v) {
      const Point<3> p = source.vertex(v);
      auto it = std::lower_bound(by_x.begin(), by_x.end(), p.x() - tolerance,
                                 [&](Index a, double x) { return m.vertices(a, 0) < x; });
      bool found = false;
      for (; !found && it != by_x.end() && m.vertices(*it, 0) <= p.x() + tolerance; ++it)
        found = (m.vertex(*it) - p).norm() <= tolerance;
      if (!found)
        throw mesh_error(path,
                         "vertex " + std::to_string(v) + " " + point_text(p) + " of " + source.name() +
                             " is no vertex of the mesh",
                         "mesh the source polyhedron with its corners as mesh points");
    }
  }

  m.boundary_facets = find_boundary_facets(m);
  m.facet_tags.assign(static_cast<std::size_t>(m.num_boundary_facets()), -1);
  if (facets.empty()) return out;
  // Physical groups of the boundary: matched to the mesh's facets by their vertices.
  std::map<std::vector<long>, const GmshElement*> group_of;
  for (const GmshElement* e : facets) {
    std::vector<long> key = e->nodes;
    std::sort(key.begin(), key.end());
    const auto [it, added] = group_of.emplace(key, e);
    if (!added && it->second->physical != e->physical)
      throw mesh_error(path,
                       "line " + std::to_string(e->line) + ": element " + std::to_string(e->id) +
                           " is in physical group " + std::to_string(e->physical) + ", and element " +
                           std::to_string(it->second->id) + " on the same nodes in group " +
                           std::to_string(it->second->physical),
                       "put each boundary surface in one physical group");
  }
  std::vector<int> tags;
  for (const auto& [key, e] : group_of) tags.push_back(e->physical);
  std::sort(tags.begin(), tags.end());
  tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    std::vector<long> key;
    for (Index k = 0; k < m.boundary_facets.cols(); ++k)
      key.push_back(tag_of_vertex[static_cast<std::size_t>(m.boundary_facets(f, k))]);
    const std::vector<long> nodes = key;
    std::sort(key.begin(), key.end());
    const auto it = group_of.find(key);
    if (it == group_of.end()) {
      std::string listing;
      for (long n : nodes) listing += (listing.empty() ? "" : ", ") + std::to_string(n);
      throw mesh_error(path,
                       "the boundary facet on nodes " + listing +
                           " is in no physical group, but other boundary facets are",
                       "add every boundary surface to a physical group (Physical Surface), or none");
    }
    m.facet_tags[static_cast<std::size_t>(f)] =
        static_cast<int>(std::lower_bound(tags.begin(), tags.end(), it->second->physical) - tags.begin());
  }
  out.physical_tags = tags;
  for (int t : tags) {
    const auto name = file.physical_names.find({2, t});
    out.names.push_back(name == file.physical_names.end() ? "" : name->second);
  }
  return out;
}

}  // namespace warpfem
