#include "fem/lagrange_element.hpp"

#include "core/error.hpp"

namespace warpfem::fem {
namespace {
// 1D Lagrange basis on nodes {0, 1, 1/2} (order 2) or {0, 1} (order 1).
void basis_1d(int order, double s, double* l, double* dl) {
  if (order == 1) {
    l[0] = 1 - s, l[1] = s;
    dl[0] = -1, dl[1] = 1;
  } else {
    l[0] = (1 - s) * (1 - 2 * s), l[1] = s * (2 * s - 1), l[2] = 4 * s * (1 - s);
    dl[0] = 4 * s - 3, dl[1] = 4 * s - 1, dl[2] = 4 - 8 * s;
  }
}
}  // namespace

LagrangeElement::LagrangeElement(CellType type, int order) : type_(type), order_(order) {
  if (order != 1 && order != 2)
    throw Error("Lagrange elements of order " + std::to_string(order) + " are not available",
                {.file = "", .key_path = "", .hint = "use order 1 or 2"});
  if (type == CellType::triangle) {
    nodes_.resize(order == 1 ? 3 : 6, 2);
    nodes_.topRows(3) << 0, 0, 1, 0, 0, 1;
    if (order == 2) nodes_.bottomRows(3) << 0.5, 0, 0.5, 0.5, 0, 0.5;
  } else if (type == CellType::quadrilateral) {
    nodes_.resize(order == 1 ? 4 : 9, 2);
    nodes_.topRows(4) << 0, 0, 1, 0, 1, 1, 0, 1;
    if (order == 2) nodes_.bottomRows(5) << 0.5, 0, 1, 0.5, 0.5, 1, 0, 0.5, 0.5, 0.5;
  } else {
    throw Error("Lagrange elements on " + to_string(type) + " cells are not available yet");
  }
}

std::string LagrangeElement::name() const {
  return std::string(type_ == CellType::triangle ? "P" : "Q") + std::to_string(order_);
}

void LagrangeElement::eval_point(double u, double v, double* phi, double* du, double* dv) const {
  if (type_ == CellType::triangle) {
    const double l0 = 1 - u - v, l1 = u, l2 = v;
    if (order_ == 1) {
      phi[0] = l0, phi[1] = l1, phi[2] = l2;
      du[0] = -1, du[1] = 1, du[2] = 0;
      dv[0] = -1, dv[1] = 0, dv[2] = 1;
      return;
    }
    phi[0] = l0 * (2 * l0 - 1), phi[1] = l1 * (2 * l1 - 1), phi[2] = l2 * (2 * l2 - 1);
    phi[3] = 4 * l0 * l1, phi[4] = 4 * l1 * l2, phi[5] = 4 * l2 * l0;
    du[0] = -(4 * l0 - 1), du[1] = 4 * l1 - 1, du[2] = 0;
    du[3] = 4 * (l0 - l1), du[4] = 4 * l2, du[5] = -4 * l2;
    dv[0] = -(4 * l0 - 1), dv[1] = 0, dv[2] = 4 * l2 - 1;
    dv[3] = -4 * l1, dv[4] = 4 * l1, dv[5] = 4 * (l0 - l2);
    return;
  }
  // Tensor products; (i, j) = index of the 1D basis in u and v for each node.
  double a[3], da[3], b[3], db[3];
  basis_1d(order_, u, a, da);
  basis_1d(order_, v, b, db);
  static const int q1[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  static const int q2[9][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0}, {1, 2}, {2, 1}, {0, 2}, {2, 2}};
  const int n = order_ == 1 ? 4 : 9;
  for (int k = 0; k < n; ++k) {
    const int i = order_ == 1 ? q1[k][0] : q2[k][0];
    const int j = order_ == 1 ? q1[k][1] : q2[k][1];
    phi[k] = a[i] * b[j];
    du[k] = da[i] * b[j];
    dv[k] = a[i] * db[j];
  }
}

MatrixX LagrangeElement::values(const Points<2>& xi) const {
  MatrixX out(xi.rows(), num_dofs());
  std::vector<double> phi(num_dofs()), du(num_dofs()), dv(num_dofs());
  for (Index p = 0; p < xi.rows(); ++p) {
    eval_point(xi(p, 0), xi(p, 1), phi.data(), du.data(), dv.data());
    for (int k = 0; k < num_dofs(); ++k) out(p, k) = phi[k];
  }
  return out;
}

std::array<MatrixX, 2> LagrangeElement::gradients(const Points<2>& xi) const {
  std::array<MatrixX, 2> out{MatrixX(xi.rows(), num_dofs()), MatrixX(xi.rows(), num_dofs())};
  std::vector<double> phi(num_dofs()), du(num_dofs()), dv(num_dofs());
  for (Index p = 0; p < xi.rows(); ++p) {
    eval_point(xi(p, 0), xi(p, 1), phi.data(), du.data(), dv.data());
    for (int k = 0; k < num_dofs(); ++k) out[0](p, k) = du[k], out[1](p, k) = dv[k];
  }
  return out;
}

void edge_shape_functions(int order, double s, double* phi) {
  double d[3];
  basis_1d(order, s, phi, d);
}

}  // namespace warpfem::fem
