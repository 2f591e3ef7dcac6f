// Density grids for heterogeneous media: a small text format (scenes/README.md):
//
//     spt-density-grid 1
//     NX NY NZ
//     v v v ...        NX·NY·NZ values, x varying fastest, then y, then z
//
// Whitespace (spaces, tabs, line breaks) separates the tokens; '#' starts a comment that runs
// to the end of its line. Values are finite and ≥ 0; each size is in [1, 512].
#pragma once
#include <string>
#include <string_view>

#include "model/media/grid_density.h"

namespace spt {

/// Parses a grid; throws LocatedError ("origin:line:column: ...") on any defect: a wrong
/// header, a bad size, a value that is not a finite number ≥ 0, too few or too many values.
DensityGrid parse_density_grid(std::string_view text, const std::string& origin);

}  // namespace spt
