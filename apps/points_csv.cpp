#include "apps/points_csv.hpp"

#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.hpp"

namespace warpfem::apps {

template <int dim>
Points<dim> read_points_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open points file", {.file = path, .key_path = "", .hint = "check the path"});
  const std::string expected = dim == 2 ? "expected two numbers \"x,y\"" : "expected three numbers \"x,y,z\"";
  std::vector<Point<dim>> pts;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (auto h = line.find('#'); h != std::string::npos) line.erase(h);
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t') c = ' ';
    std::istringstream ls(line);
    std::string first;
    if (!(ls >> first)) continue;
    Point<dim> p;
    std::istringstream fs(first);
    if (!(fs >> p(0))) {
      if (pts.empty() && number == 1) continue;  // header line such as "x,y"
      throw Error("line " + std::to_string(number) + ": " + expected,
                  {.file = path, .key_path = "", .hint = "one point per line"});
    }
    for (int d = 1; d < dim; ++d)
      if (!(ls >> p(d)))
        throw Error("line " + std::to_string(number) + ": " + expected,
                    {.file = path, .key_path = "", .hint = "one point per line"});
    pts.push_back(p);
  }
  Points<dim> out(static_cast<Index>(pts.size()), dim);
  for (std::size_t i = 0; i < pts.size(); ++i) out.row(static_cast<Index>(i)) = pts[i].transpose();
  return out;
}

template Points<2> read_points_csv<2>(const std::string&);
template Points<3> read_points_csv<3>(const std::string&);

}  // namespace warpfem::apps
