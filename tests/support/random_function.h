// Random four-bar function generators and the pairs they make, for the function-generation
// tests and the benchmark.
#ifndef LINKFIT_TESTS_SUPPORT_RANDOM_FUNCTION_H_
#define LINKFIT_TESTS_SUPPORT_RANDOM_FUNCTION_H_

#include <random>
#include <string>
#include <vector>

#include "lib/function_four_bar.h"

namespace linkfit::testing {

// A random four-bar of ground 1: cranks and coupler in [0.3, 2.5], with relative offsets drawn
// in [-pi, pi) when `offsets` (else 0), either assembly.
FunctionFourBar RandomFunctionFourBar(std::mt19937_64& rng, bool offsets);

// A four-bar and `count` pairs it generates (radians, in the task's angles: t2 - offset): inputs
// increasing over up to `spread` radians of the first pair's closure interval, on its assembly,
// at least 0.1 rad apart, every transmission angle at least 20 degrees over them. Drawn again
// until such pairs exist.
struct FunctionTask {
  FunctionFourBar four_bar;
  std::vector<FunctionPair> pairs;
};
FunctionTask RandomFunctionTask(std::mt19937_64& rng, int count, bool offsets, double spread = 2.0);

// The task's JSON text, its angles printed to `digits` significant digits (0: full precision):
// {"problem": "function", "angles": "absolute" | "relative", "pairs": [...]}.
std::string FunctionTaskJson(const std::vector<FunctionPair>& pairs, bool relative, int digits);

}  // namespace linkfit::testing

#endif  // LINKFIT_TESTS_SUPPORT_RANDOM_FUNCTION_H_
