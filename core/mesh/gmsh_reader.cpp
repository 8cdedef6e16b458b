#include "core/mesh/gmsh_reader.hpp"

#include <fstream>
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

 private:
  std::string path_;
  std::ifstream in_;
  int number_ = 0;
};

int nodes_of_type(int type) {
  switch (type) {
    case 2: return 3;   // 3-node triangle
    case 3: return 4;   // 4-node quadrangle
    default: return 0;  // anything else is skipped
  }
}

}  // namespace

Mesh<2> read_gmsh(const std::string& path, const Polygon& source) {
  LineReader r(path);
  r.expect("$MeshFormat");
  double version = 0;
  int file_type = 0;
  r.next_stream("the format line") >> version >> file_type;
  if (file_type != 0) r.fail("binary .msh files are not supported");
  if (version < 2.0 || version >= 5.0) r.fail("unsupported format version " + std::to_string(version));
  const bool v4 = version >= 4.0;
  r.expect("$EndMeshFormat");

  std::unordered_map<long, Index> node_index;
  std::vector<Point<2>> nodes;
  std::vector<std::vector<long>> cells;
  int cell_nodes = 0;
  std::string line;
  while (r.next(line)) {
    if (line == "$Nodes") {
      auto head = r.next_stream("the node count");
      long blocks = 0, count = 0;
      if (v4) {
        if (!(head >> blocks >> count)) r.fail("expected the numbers of node blocks and nodes");
        for (long b = 0; b < blocks; ++b) {
          long dim, tag, parametric, n;
          if (!(r.next_stream("a node block") >> dim >> tag >> parametric >> n))
            r.fail("expected \"dim tag parametric count\" of a node block");
          // Grown line by line: a count the file does not back up allocates nothing.
          std::vector<long> tags;
          for (long i = 0; i < n; ++i)
            if (!(r.next_stream("a node tag") >> tags.emplace_back())) r.fail("expected a node tag");
          for (long i = 0; i < n; ++i) {
            double x, y, z;
            if (!(r.next_stream("node coordinates") >> x >> y >> z))
              r.fail("expected three node coordinates");
            node_index[tags[i]] = static_cast<Index>(nodes.size());
            nodes.emplace_back(x, y);
          }
        }
      } else {
        if (!(head >> count)) r.fail("expected the number of nodes");
        for (long i = 0; i < count; ++i) {
          long id;
          double x, y, z;
          if (!(r.next_stream("a node") >> id >> x >> y >> z)) r.fail("expected \"id x y z\"");
          node_index[id] = static_cast<Index>(nodes.size());
          nodes.emplace_back(x, y);
        }
      }
      r.expect("$EndNodes");
    } else if (line == "$Elements") {
      auto head = r.next_stream("the element count");
      auto add_cell = [&](int type, std::istringstream& in) {
        const int n = nodes_of_type(type);
        if (n == 0) return;
        if (cell_nodes != 0 && cell_nodes != n)
          r.fail("mixed triangles and quadrilaterals are not supported");
        cell_nodes = n;
        std::vector<long> c(static_cast<std::size_t>(n));
        for (auto& v : c)
          if (!(in >> v)) r.fail("too few node ids for the element");
        cells.push_back(std::move(c));
      };
      if (v4) {
        long blocks = 0, count = 0;
        if (!(head >> blocks >> count)) r.fail("expected the numbers of element blocks and elements");
        for (long b = 0; b < blocks; ++b) {
          long dim, tag, type, n;
          if (!(r.next_stream("an element block") >> dim >> tag >> type >> n))
            r.fail("expected \"dim tag type count\" of an element block");
          for (long i = 0; i < n; ++i) {
            auto in = r.next_stream("an element");
            long id;
            if (!(in >> id)) r.fail("expected an element id");
            if (dim == 2) add_cell(static_cast<int>(type), in);
          }
        }
      } else {
        long count = 0;
        if (!(head >> count)) r.fail("expected the number of elements");
        for (long i = 0; i < count; ++i) {
          auto in = r.next_stream("an element");
          long id, type, ntags, t;
          if (!(in >> id >> type >> ntags)) r.fail("expected \"id type tag-count tags... node-ids...\"");
          // Each tag must be on the line (a huge tag count must not loop on a failed stream).
          for (long k = 0; k < ntags; ++k)
            if (!(in >> t)) r.fail("fewer tags than the element's tag count");
          add_cell(static_cast<int>(type), in);
        }
      }
      r.expect("$EndElements");
    } else if (!line.empty() && line[0] == '$') {
      // Skip sections we do not use ($PhysicalNames, $Entities, ...).
      const std::string end = "$End" + line.substr(1);
      while (r.next(line) && line != end) {
      }
    }
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
      auto it = node_index.find(cells[c][k]);
      if (it == node_index.end()) r.fail("element refers to unknown node " + std::to_string(cells[c][k]));
      auto [u, inserted] = used.try_emplace(cells[c][k], static_cast<Index>(verts.size()));
      if (inserted) verts.push_back(nodes[it->second]);
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
    throw Error(
        "the mesh covers area " + std::to_string(area) + " but the source polygon has area " +
            std::to_string(source.signed_area()),
        {.file = path, .key_path = "mesh.file", .hint = "mesh exactly the source polygon of map.source"});
  m.boundary_facets = find_boundary_facets(m);
  try {
    tag_boundary_facets(m, source);
  } catch (const Error& e) {
    throw Error(e.message(), {.file = path, .key_path = "mesh.file", .hint = e.context().hint});
  }
  return m;
}

}  // namespace warpfem
