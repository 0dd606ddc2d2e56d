// The stiff cloth of tests/support/stiff_cloth.hpp at 100 x 100 (30,000 unknowns): a Newton
// iteration costs about 0.3 s (a supernodal Cholesky, twice where the exact Hessian is
// indefinite) and convergence in the buckling fall takes 30 or more, so Newton is capped at 5
// iterations a step. About 100 s on one core: ctest label "large", left out of the default test
// presets; run it with `ctest --preset large` (it prints a line per frame).
#include "support/stiff_cloth.hpp"

namespace weft {
namespace {

TEST(StiffClothLarge, HundredByHundredWithFiveNewtonIterationsAStepStaysBoundedAndSettles) {
  const int capped_steps = test::expect_bounded_and_settled(100, 5, 96);
  EXPECT_GT(capped_steps, 0);
}

}  // namespace
}  // namespace weft
