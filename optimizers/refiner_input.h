// The argument checks every least-squares refiner and search shares: the characteristic length,
// one positive weight per pose (or none) and one exact flag per pose (or none).
#ifndef LINKFIT_OPTIMIZERS_REFINER_INPUT_H_
#define LINKFIT_OPTIMIZERS_REFINER_INPUT_H_

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace linkfit {

// Throws std::invalid_argument, the message starting with "<who>: ", when `length` is not
// positive and finite, when `weights` or `exact` (if non-null) is non-empty with a size other
// than `pose_count`, or when a weight is not positive and finite. Returns the mean weight (1 for
// no weights), by which the refiners divide the weights so that their overall scale is free.
inline double CheckRefinerInput(const std::string& who, size_t pose_count, double length,
                                const std::vector<double>& weights,
                                const std::vector<bool>* exact = nullptr) {
  const std::string where = who + ": ";
  if (!(length > 0.0) || !std::isfinite(length)) {
    throw std::invalid_argument(where + "length must be positive and finite");
  }
  if (!weights.empty() && weights.size() != pose_count) {
    throw std::invalid_argument(where + std::to_string(weights.size()) + " weights for " +
                                std::to_string(pose_count) + " poses");
  }
  if (exact != nullptr && !exact->empty() && exact->size() != pose_count) {
    throw std::invalid_argument(where + std::to_string(exact->size()) + " exact flags for " +
                                std::to_string(pose_count) + " poses");
  }
  if (weights.empty()) return 1.0;
  double weight_sum = 0.0;
  for (double weight : weights) {
    if (!(weight > 0.0) || !std::isfinite(weight)) {
      throw std::invalid_argument(where + "weights must be positive and finite");
    }
    weight_sum += weight;
  }
  return weight_sum / static_cast<double>(weights.size());
}

}  // namespace linkfit

#endif  // LINKFIT_OPTIMIZERS_REFINER_INPUT_H_
