#include "tests/support/random_function.h"

#include <cmath>
#include <cstdio>

namespace linkfit::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The transmission angle at the output pin, folded to [0, 90] degrees, at crank angle t2.
double TransmissionDeg(const FunctionFourBar& f, double t2) {
  const double a = f.input_length, b = f.coupler_length, c = f.output_length, d = f.ground;
  const double s = a * a + d * d - 2.0 * a * d * std::cos(t2);
  const double cos_mu = (b * b + c * c - s) / (2.0 * b * c);
  if (std::abs(cos_mu) > 1.0) return 0.0;
  return std::acos(std::abs(cos_mu)) * 180.0 / kPi;
}

}  // namespace

FunctionFourBar RandomFunctionFourBar(std::mt19937_64& rng, bool offsets) {
  std::uniform_real_distribution<double> length(0.3, 2.5), angle(-kPi, kPi);
  FunctionFourBar f;
  f.ground = 1.0;
  f.input_length = length(rng);
  f.coupler_length = length(rng);
  f.output_length = length(rng);
  f.input_offset = offsets ? angle(rng) : 0.0;
  f.output_offset = offsets ? angle(rng) : 0.0;
  f.assembly = std::bernoulli_distribution(0.5)(rng) ? 1 : -1;
  return f;
}

FunctionTask RandomFunctionTask(std::mt19937_64& rng, int count, bool offsets, double spread) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (;;) {
    FunctionTask task;
    task.four_bar = RandomFunctionFourBar(rng, offsets);
    const FunctionFourBar& f = task.four_bar;
    // A first input that assembles, then steps forward while every input assembles with a good
    // transmission angle (so the pairs stay on the first pair's assembly and interval).
    const double first = -kPi + 2.0 * kPi * unit(rng);
    const double step = spread / std::max(count - 1, 1);
    bool good = true;
    for (int j = 0; j < count && good; ++j) {
      const double phi = first + j * step * (0.8 + 0.4 * unit(rng) * (j > 0));
      // Every input between the previous pair and this one keeps a good transmission.
      const double previous = task.pairs.empty() ? phi : task.pairs.back().input;
      for (int k = 0; k <= 10 && good; ++k) {
        const double between = previous + (phi - previous) * k / 10.0;
        if (TransmissionDeg(f, f.input_offset + between) < 20.0) good = false;
      }
      double psi;
      if (!good || !f.Output(phi, &psi)) {
        good = false;
        break;
      }
      FunctionPair pair;
      pair.input = phi;
      pair.output = psi;
      task.pairs.push_back(pair);
    }
    if (!good) continue;
    for (size_t j = 1; j < task.pairs.size(); ++j) {
      if (task.pairs[j].input - task.pairs[j - 1].input < 0.1) good = false;
    }
    if (good) return task;
  }
}

std::string FunctionTaskJson(const std::vector<FunctionPair>& pairs, bool relative, int digits) {
  const auto number = [&](double radians) {
    char text[64];
    const double degrees = radians * 180.0 / kPi;
    if (digits > 0) {
      std::snprintf(text, sizeof(text), "%.*e", digits - 1, degrees);
    } else {
      std::snprintf(text, sizeof(text), "%.17g", degrees);
    }
    return std::string(text);
  };
  std::string json = std::string("{\"problem\": \"function\", \"angles\": \"") +
                     (relative ? "relative" : "absolute") + "\", \"pairs\": [";
  for (size_t j = 0; j < pairs.size(); ++j) {
    json += (j > 0 ? ", " : "") + std::string("{\"input_deg\": ") + number(pairs[j].input) +
            ", \"output_deg\": " + number(pairs[j].output) + "}";
  }
  return json + "]}";
}

}  // namespace linkfit::testing
