// The thesis's own calibration (Cooke, section 4.2, equations 4.1 and 4.2) and the
// decomposition it printed for each camera, for reproducing those figures.
//
// The matrices were printed with two decimals, so their third rows (-0.01, -0.24, 0.01) carry
// up to 50% rounding error in their small entries, and the image centre is very sensitive to
// them (du0/dC31 = C11/|m3|^2, about 4000 px per unit: +-20 px for +-0.005). Decomposing the
// printed matrices therefore cannot give the printed figures exactly. ClosestWithinRounding
// searches the third row inside its rounding box (each entry +-0.005) for the matrix whose
// decomposition is nearest the printed figures: that shows the printed figures are what the
// printed matrices, at full precision, decompose to.
#pragma once

#include <array>
#include <string>

#include "common/geometry/decomposition.h"

namespace igms::calibration {

struct PrintedDecomposition {
  double ku, kv, u0, v0, x, y, z, theta, phi, psi;
};

struct ThesisCamera {
  std::string name;
  geometry::Matrix34 C;
  PrintedDecomposition printed;
};

// Left (4.1) and right (4.2).
std::array<ThesisCamera, 2> ThesisCameras();

// The ten printed quantities of a decomposition, in PrintedDecomposition's order, using the
// thesis's angle forms (printed_theta, printed_psi).
std::array<double, 10> AsPrinted(const geometry::ThesisDecomposition& d);
std::array<double, 10> AsArray(const PrintedDecomposition& p);
extern const std::array<const char*, 10> kPrintedNames;

struct RoundingFit {
  geometry::Matrix34 C;  // the printed matrix with its third row adjusted
  geometry::ThesisDecomposition decomposition;
  double max_row3_change = 0;  // largest change to a third-row entry (<= 0.005)
};

// Grid search (steps of 0.00025) over the third row of `camera.C` within +-0.005 per entry,
// minimising the relative mismatch of the decomposition with the printed figures.
RoundingFit ClosestWithinRounding(const ThesisCamera& camera);

}  // namespace igms::calibration
