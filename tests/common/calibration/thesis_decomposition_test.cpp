// The thesis's printed decomposition (section 4.2) reproduced from its printed matrices.
#include <gtest/gtest.h>

#include "common/sim/thesis_reference.h"

namespace igms::calibration {
namespace {

TEST(ThesisDecomposition, PrintedMatricesDecomposeNearThePrintedFigures) {
  for (const auto& cam : ThesisCameras()) {
    const auto d = geometry::DecomposeThesis(cam.C);
    ASSERT_TRUE(d.ok());
    // Straight from the two-decimal matrices: rounding of the third row limits agreement
    // (see thesis_reference.h): scales within 2%, centres within 0.5 in, angles 0.03 rad,
    // image centre within 20 px.
    EXPECT_NEAR(d->ku / cam.printed.ku, 1.0, 0.02) << cam.name;
    EXPECT_NEAR(d->kv / cam.printed.kv, 1.0, 0.02) << cam.name;
    EXPECT_NEAR(d->u0, cam.printed.u0, 20) << cam.name;
    EXPECT_NEAR(d->v0, cam.printed.v0, 5) << cam.name;
    EXPECT_NEAR(d->center.x(), cam.printed.x, 0.5) << cam.name;
    EXPECT_NEAR(d->center.y(), cam.printed.y, 0.5) << cam.name;
    EXPECT_NEAR(d->center.z(), cam.printed.z, 0.5) << cam.name;
    EXPECT_NEAR(d->printed_theta, cam.printed.theta, 0.03) << cam.name;
    EXPECT_NEAR(d->phi, cam.printed.phi, 0.01) << cam.name;
    EXPECT_NEAR(d->printed_psi, cam.printed.psi, 0.02) << cam.name;
  }
}

TEST(ThesisDecomposition, WithinRoundingTheFiguresAreReproducedToPrintedPrecision) {
  for (const auto& cam : ThesisCameras()) {
    const auto fit = ClosestWithinRounding(cam);
    EXPECT_LE(fit.max_row3_change, 0.005 + 1e-12);
    const auto got = AsPrinted(fit.decomposition);
    const auto want = AsArray(cam.printed);
    // Scales to 0.1%, image centre to 0.5 px, centre to 0.02 in, angles to the printed
    // digit (0.01 rad, phi 0.001).
    const double tolerance[10] = {0.001 * 945, 0.001 * 1192, 0.5,   0.5,    0.02,
                                  0.02,        0.02,         0.006, 0.0012, 0.006};
    for (int k = 0; k < 10; ++k) {
      EXPECT_NEAR(got[k], want[k], tolerance[k]) << cam.name << " " << kPrintedNames[k];
    }
    EXPECT_LT(std::abs(fit.decomposition.skew), 1e-3);
  }
}

TEST(ThesisDecomposition, ComposedFromPrintedFiguresGivesThePrintedMatrix) {
  for (const auto& cam : ThesisCameras()) {
    geometry::ThesisDecomposition d;
    d.ku = cam.printed.ku;
    d.kv = cam.printed.kv;
    d.u0 = cam.printed.u0;
    d.v0 = cam.printed.v0;
    d.center = Eigen::Vector3d(cam.printed.x, cam.printed.y, cam.printed.z);
    d.theta = cam.printed.theta + M_PI / 2;
    d.phi = cam.printed.phi;
    d.psi = M_PI - cam.printed.psi;
    d.lambda = 1;
    const geometry::Matrix34 C = geometry::ComposeThesis(d);
    // Third row within its printed rounding; the others within 1% (the figures' own digits).
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(C(2, j), cam.C(2, j), 0.005) << cam.name;
    EXPECT_LT((C.topRows<2>() - cam.C.topRows<2>()).norm() / cam.C.topRows<2>().norm(), 0.01);
  }
}

}  // namespace
}  // namespace igms::calibration
