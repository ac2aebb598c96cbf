#include "fitting/function_generation.h"

#include <Eigen/Dense>
#include <cmath>

#include "fitting/planar_burmester.h"
#include "lib/four_bar_closure.h"

namespace linkfit {
namespace {

// Exact pairs in the linear fits: their rows weighted this much more (squared weight 1e6).
constexpr double kExactRowWeight = 1e3;

void Say(std::string* why, const std::string& text) {
  if (why != nullptr) *why = text;
}

// The four-bar of Freudenstein's coefficients K (file comment of the header), or false with the
// reason.
bool FourBarOfCoefficients(const Eigen::Vector3d& k, double ground, FunctionFourBar* four_bar,
                           std::string* why) {
  if (!(k.x() > 0.0)) {
    Say(why, k.x() == 0.0 ? "the pairs give an input crank of infinite length"
                          : "the pairs give a negative input crank: it would point opposite its "
                            "prescribed angle");
    return false;
  }
  if (!(k.y() > 0.0)) {
    Say(why, k.y() == 0.0 ? "the pairs give an output crank of infinite length"
                          : "the pairs give a negative output crank: it would point opposite its "
                            "prescribed angle");
    return false;
  }
  const double a = ground / k.x(), c = ground / k.y();
  const double coupler_squared = a * a + c * c + ground * ground - 2.0 * a * c * k.z();
  if (!(coupler_squared > 0.0) || !std::isfinite(coupler_squared)) {
    Say(why, "the pairs give no real coupler length (b^2 <= 0)");
    return false;
  }
  four_bar->ground = ground;
  four_bar->input_length = a;
  four_bar->output_length = c;
  four_bar->coupler_length = std::sqrt(coupler_squared);
  return four_bar->Valid();
}

// Sets the assembly that meets the first pair (the first pair that assembles decides when the
// first does not).
void ChooseAssembly(const std::vector<FunctionPair>& pairs, FunctionFourBar* four_bar) {
  four_bar->assembly = 1;
  for (const FunctionPair& pair : pairs) {
    const int sigma = NearestAssembly(*four_bar, pair);
    if (sigma != 0) {
      four_bar->assembly = sigma;
      return;
    }
  }
}

}  // namespace

int FreudensteinWithOffsets(const std::vector<FunctionPair>& pairs, double ground,
                            double input_offset, double output_offset,
                            std::vector<FunctionFourBar>* four_bars, std::string* why) {
  const int n = static_cast<int>(pairs.size());
  if (n < 3) {
    Say(why, "Freudenstein's equation needs three pairs");
    return 0;
  }
  // Eq. (Fr): [cos t4, -cos t2, 1] K = cos(t2 - t4), one row per pair.
  Eigen::MatrixXd rows(n, 3);
  Eigen::VectorXd right(n);
  for (int j = 0; j < n; ++j) {
    const double t2 = input_offset + pairs[j].input, t4 = output_offset + pairs[j].output;
    const double w = std::sqrt(pairs[j].weight) * (pairs[j].exact ? kExactRowWeight : 1.0);
    rows.row(j) << w * std::cos(t4), -w * std::cos(t2), w;
    right(j) = w * std::cos(t2 - t4);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(rows, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::Vector3d sigma = svd.singularValues();
  if (!(sigma(2) > 1e-12 * sigma(0))) {
    Say(why,
        "the pairs are dependent in Freudenstein's equation (e.g. inputs or outputs "
        "repeated): they do not determine a four-bar");
    return 0;
  }
  const Eigen::Vector3d k = svd.solve(right);
  FunctionFourBar four_bar;
  if (!FourBarOfCoefficients(k, ground, &four_bar, why)) return 0;
  four_bar.input_offset = input_offset;
  four_bar.output_offset = output_offset;
  ChooseAssembly(pairs, &four_bar);
  four_bars->push_back(four_bar);
  return 1;
}

int SolveFreudenstein(const std::vector<FunctionPair>& pairs, double ground,
                      std::vector<FunctionFourBar>* four_bars, std::string* why) {
  return FreudensteinWithOffsets(pairs, ground, 0.0, 0.0, four_bars, why);
}

std::vector<PlanarPose> RelativeOutputPoses(const std::vector<FunctionPair>& pairs, double ground) {
  std::vector<PlanarPose> poses;
  poses.reserve(pairs.size());
  for (const FunctionPair& pair : pairs) {
    // The output link's frame O (origin B = (d, 0), turned by psi) seen from the input link's
    // frame I (origin A, turned by phi).
    poses.emplace_back(ground * std::cos(pair.input), -ground * std::sin(pair.input),
                       pair.output - pair.input);
  }
  return poses;
}

int SolveRelativeFunction(const std::vector<FunctionPair>& pairs, double ground,
                          const FunctionGenerationOptions& options,
                          std::vector<FunctionFourBar>* four_bars, std::string* why) {
  if (pairs.size() < 5) {
    Say(why, "relative angles need five pairs");
    return 0;
  }
  PlanarBurmesterOptions burmester;
  burmester.precision = options.precision;
  std::vector<PlanarDyad> dyads;
  PlanarBurmesterSummary summary;
  SolvePlanarBurmester(RelativeOutputPoses(pairs, ground), burmester, &dyads, &summary);
  if (summary.degenerate) {
    Say(why,
        "the pairs leave a family of four-bars (the relative motion's five poses are "
        "dependent)");
    return 0;
  }
  int count = 0, sliders = 0;
  for (const PlanarDyad& dyad : dyads) {
    if (dyad.type != DyadType::kRR) {
      ++sliders;
      continue;
    }
    const Eigen::Vector2d& pin_in_input = dyad.fixed_pivot;    // P, in the input link's frame
    const Eigen::Vector2d& pin_in_output = dyad.moving_pivot;  // Q, in the output link's frame
    const double tolerance = options.trivial_tolerance * ground;
    if (pin_in_input.norm() < tolerance && pin_in_output.norm() < tolerance) continue;  // ground
    FunctionFourBar four_bar;
    four_bar.ground = ground;
    four_bar.input_length = pin_in_input.norm();
    four_bar.output_length = pin_in_output.norm();
    four_bar.coupler_length = dyad.radius;
    four_bar.input_offset = std::atan2(pin_in_input.y(), pin_in_input.x());
    four_bar.output_offset = std::atan2(pin_in_output.y(), pin_in_output.x());
    if (!four_bar.Valid()) continue;
    ChooseAssembly(pairs, &four_bar);
    four_bars->push_back(four_bar);
    ++count;
  }
  if (count == 0) {
    Say(why, sliders > 0 ? "the relative motion's real dyads are sliders: no four-bar of cranks"
                         : "the relative motion has no real dyad besides the ground link: no "
                           "four-bar meets the pairs");
  }
  return count;
}

}  // namespace linkfit
