// Planar dyads and their residuals.
//   RR: the moving pivot (in E) stays on a circle about the fixed pivot (in Sigma).
//   PR: the moving pivot (in E) stays on a line fixed in Sigma (a slider).
//   RP: the fixed pivot (in Sigma) stays on a line fixed in E (the inversion of PR).
// A dyad's residual at a pose is the signed distance of its constrained point from its
// circle or line, in length units.
#ifndef LINKFIT_LIB_DYAD_H_
#define LINKFIT_LIB_DYAD_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "lib/planar_pose.h"

namespace linkfit {

enum class DyadType { kRR, kPR, kRP };

const char* DyadTypeName(DyadType type);  // "RR", "PR", "RP"

struct PlanarDyad {
  DyadType type = DyadType::kRR;
  // RR and RP: the ground pivot, in Sigma.
  Eigen::Vector2d fixed_pivot = Eigen::Vector2d::Zero();
  // RR and PR: the coupler pivot, in E.
  Eigen::Vector2d moving_pivot = Eigen::Vector2d::Zero();
  // RR: the crank length |moving pivot in Sigma - fixed pivot|.
  double radius = 0.0;
  // PR: a point of the slider line in Sigma; RP: a point of the line in E.
  Eigen::Vector2d line_point = Eigen::Vector2d::Zero();
  // PR: unit direction of the slider line in Sigma; RP: in E.
  Eigen::Vector2d line_direction = Eigen::Vector2d::UnitX();

  static PlanarDyad RR(const Eigen::Vector2d& fixed_pivot, const Eigen::Vector2d& moving_pivot,
                       double radius);
  static PlanarDyad PR(const Eigen::Vector2d& moving_pivot, const Eigen::Vector2d& line_point,
                       const Eigen::Vector2d& line_direction);
  static PlanarDyad RP(const Eigen::Vector2d& fixed_pivot, const Eigen::Vector2d& line_point,
                       const Eigen::Vector2d& line_direction);

  // Signed distance of the constrained point from its circle or line at `pose`.
  double Residual(const PlanarPose& pose) const;
  // The same for a pose given by its rotation matrix and origin (callers that evaluate many
  // residuals build the rotation once; inline, as solvers call it in their inner loops).
  double Residual(const Eigen::Matrix2d& rotation, const Eigen::Vector2d& origin) const {
    // Signed distances from lines are positive to the left of the line direction.
    const Eigen::Vector2d normal(-line_direction.y(), line_direction.x());
    switch (type) {
      case DyadType::kRR:
        return (rotation * moving_pivot + origin - fixed_pivot).norm() - radius;
      case DyadType::kPR:
        return normal.dot(rotation * moving_pivot + origin - line_point);
      case DyadType::kRP:
        return normal.dot(rotation.transpose() * (fixed_pivot - origin) - line_point);
    }
    return 0.0;
  }
  // Whether the parameters its type uses are finite (and a line direction is not zero).
  bool AllFinite() const;
  // Largest |residual| over the poses.
  double MaxResidual(const std::vector<PlanarPose>& poses) const;

  // The same dyad with the roles of Sigma and E exchanged: RR stays RR with fixed and moving
  // pivots swapped, PR of a motion is RP of the inverted motion and vice versa.
  PlanarDyad Inverted() const;

  // Whether the type has a fixed pivot (RR, RP) and a moving pivot (RR, PR).
  bool HasFixedPivot() const { return type != DyadType::kPR; }
  bool HasMovingPivot() const { return type != DyadType::kRP; }

  // Line direction angle in degrees, in [0, 180) (PR: in Sigma; RP: in E).
  double LineAngleDeg() const;
  // Canonical line point: the foot of the perpendicular from the frame origin.
  Eigen::Vector2d LineFoot() const;
};

// Maps a dyad found in similarity-transformed frames back: `sigma` maps the transformed fixed
// frame to the original one, `epsilon` the transformed moving frame to the original one (both
// with the same scale).
PlanarDyad TransformDyad(const PlanarDyad& dyad, const Similarity2& sigma,
                         const Similarity2& epsilon);

}  // namespace linkfit

#endif  // LINKFIT_LIB_DYAD_H_
