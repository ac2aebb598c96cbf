// Pictures of tasks and mechanisms: a static SVG with one panel per mechanism, and an animation
// of one mechanism through its cycle. Everything is drawn in the fixed frame Sigma.
#ifndef LINKFIT_APPS_PICTURE_H_
#define LINKFIT_APPS_PICTURE_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "lib/dyad.h"
#include "lib/planar_pose.h"

namespace linkfit {

struct PictureMechanism {
  std::string title;                // e.g. "1: 4R, crank-rocker"
  std::vector<std::string> labels;  // defects and remarks, written on the panel
  PlanarDyad input;                 // the driven dyad
  PlanarDyad output;
  PlanarPose first_pose;                       // coupler pose at which the links are drawn
  std::vector<Eigen::Vector2d> coupler_curve;  // path of E's origin, in Sigma (may be empty)
  std::vector<PlanarPose> cycle;               // coupler poses over one cycle, for the animation
};

struct Picture {
  std::string title;                         // the task (file name)
  std::vector<PlanarPose> task_poses;        // drawn as small frames
  double length = 1.0;                       // characteristic length L (sizes of marks)
  std::vector<PictureMechanism> mechanisms;  // one panel each; a panel of poses only if empty
  // Four poses: the Burmester curves, as polylines in Sigma (circle points mapped by the first
  // pose), drawn in every panel.
  std::vector<std::vector<Eigen::Vector2d>> center_point_curves;
  std::vector<std::vector<Eigen::Vector2d>> circle_point_curves;
  std::vector<Eigen::Vector2d> path_points;  // path problems: the points to pass, marked
  // What the coupler curve traces (path problems put E's origin at the coupler point).
  std::string coupler_curve_label = "coupler curve (E origin)";
};

// A standalone SVG document (one panel per mechanism, in a grid).
std::string RenderSvg(const Picture& picture);

// An animation of mechanism `index` through its cycle: an SVG with SMIL animation, or an HTML
// page (html = true) that animates the same drawing with a few lines of script.
std::string RenderAnimation(const Picture& picture, size_t index, bool html);

}  // namespace linkfit

#endif  // LINKFIT_APPS_PICTURE_H_
