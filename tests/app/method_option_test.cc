// The method choice (LadderMethod): one parse of the CLI's and the bindings' names, the names the
// outputs print, and the solver settings each rung stands for.
#include <catch2/catch.hpp>
#include <string>

#include "gearnvh/model/input_error.h"
#include "simulate_command.h"

namespace gearnvh {
namespace {

TEST_CASE("a method's name parses to its rung and prints as it was written", "[app][method]") {
  const LadderMethod m =
      GENERATE(LadderMethod::kV1, LadderMethod::kV2, LadderMethod::kV3, LadderMethod::kFused);
  const std::string name = LadderMethodName(m);
  INFO(name);
  CHECK(app::ParseMethod(name) == m);
  SolverOptions options;
  ApplyLadderMethod(m, options);
  CHECK(options.events == EventMethodOf(m));
  // The event paths' own names are the rungs' (kFused locates by V3).
  CHECK(std::string(EventMethodName(options.events)) == (m == LadderMethod::kFused ? "v3" : name));
  CHECK(options.method ==
        (m == LadderMethod::kFused ? SolverMethod::kFused : SolverMethod::kStepped));
}

TEST_CASE("an unknown method is refused naming the option, the value and every choice",
          "[app][method]") {
  for (const std::string bad : {"v4", "V3", "", "fused "}) {
    INFO("'" << bad << "'");
    try {
      (void)app::ParseMethod(bad, "method");
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.path() == "method");
      CHECK(e.rule() == "must be one of v1, v2, v3, fused");
    }
  }
  CHECK_THROWS_AS(app::ParseMethod("v5"), InputError);
}

}  // namespace
}  // namespace gearnvh
