#pragma once
// The parameters of an "output" section, shared by the output structs of
// Poisson and elasticity runs (each holds its own defaults).

#include "core/parameters.hpp"

namespace warpfem::io {

/// `files` says which files `name` names.
template <class S>
void add_output_parameters(ParameterTable<S>& t, const std::string& files) {
  t.text("directory", &S::directory,
         "where files go (created if needed); a relative directory is relative to the config file's "
         "directory, so a run started elsewhere writes next to its config (the log names the directory). "
         "`--output-dir` on the command line overrides it (relative to the working directory)");
  t.text("name", &S::name, "base name (without `/`): " + files);
  t.flag("vtk", &S::vtk, "write VTK output");
  t.integer("vtk_order", &S::vtk_order, 0, 2, "order of the Lagrange cells written")
      .with_type("0, 1 or 2")
      .with_default("0 = 2 for a warped (non-affine) map, else the element order");
  t.choice("compression", &S::compression, {"none", "lz4", "zlib"},
           "compressor of the binary data; `\"zlib\"` makes the file smaller and takes several times longer "
           "to write, `\"lz4\"` is in between (figures: BENCHMARKS.md, \"Output\")");
  t.choice(
      "cells", &S::cells, {"curved", "linear"},
      "`\"linear\"`: straight triangles/quadrilaterals through the vertices only (`vtk_order` 1) — a "
      "quarter of the points of curved P1 output, for huge runs; P2 values are shown at the vertices only");
}

}  // namespace warpfem::io
