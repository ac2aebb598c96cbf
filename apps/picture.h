// Pictures of tasks and mechanisms: a static SVG with one panel per mechanism, and an animation
// of one mechanism through its cycle. Everything is drawn in the fixed frame Sigma.
#ifndef LINKFIT_APPS_PICTURE_H_
#define LINKFIT_APPS_PICTURE_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "lib/design_constraints.h"
#include "lib/dyad.h"
#include "lib/planar_pose.h"
#include "lib/result.h"
#include "lib/task.h"

namespace linkfit {

struct PictureMechanism {
  std::string title;                // e.g. "1: 4R, crank-rocker"
  std::vector<std::string> labels;  // defects and remarks, written on the panel
  PlanarDyad input;                 // the driven dyad
  PlanarDyad output;
  PlanarPose first_pose;                       // coupler pose at which the links are drawn
  std::vector<Eigen::Vector2d> coupler_curve;  // path of E's origin, in Sigma (may be empty)
  std::vector<PlanarPose> cycle;               // coupler poses over one cycle, for the animation
  // A linkage drawn by its joints (six-bars; the dyads above are then unused): each body's joints
  // as indices into the joints' places (body 0 the ground, `task_body` the body E is fixed to),
  // their places in Sigma at `first_pose` and at each pose of `cycle`, and their names.
  struct Joints {
    std::vector<std::vector<int>> bodies;
    int task_body = 0;
    std::vector<std::string> names;
    std::vector<Eigen::Vector2d> at_first;
    std::vector<std::vector<Eigen::Vector2d>> cycle;
  };
  std::optional<Joints> joints;
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
  // The task's design constraints' pivot boxes (lib/design_constraints.h): the fixed pivots' in
  // Sigma, drawn in every panel; the moving pivots' in E (motion), drawn where E is in each
  // mechanism's panel.
  std::optional<PlanarBox> fixed_pivots_box;
  std::optional<PlanarBox> moving_pivots_box;
};

// The picture of a solved task: planar motion (its poses, its mechanisms in ranked order, at most
// `max_panels`, and for four poses the Burmester curves; planar data in a spatial task in their
// plane) or a path task (its points, and its four-bars at the first point with the coupler
// point's curve). Nothing for a spatial platform, with the reason in *why.
std::optional<Picture> TaskPicture(const std::string& title, const Task& task,
                                   const TaskResult& result, size_t max_panels,
                                   std::string* why = nullptr);

// The picture's geometry as JSON, for drawing elsewhere (linkfit.plot): "kind": "planar",
// "title", "length", "task_poses" ([x, y, theta] in Sigma, theta in radians), "path_points",
// "center_point_curves" and "circle_point_curves" (polylines in Sigma), "coupler_curve_label",
// "fixed_pivots_box" ([x0, y0, x1, y1] in Sigma) and "moving_pivots_box" (in E), when given,
// "view" (the panel's region, [x0, y0, x1, y1], for a panel without mechanism) and "mechanisms":
// each with "title", "labels", "input" and "output" dyads ("type", "fixed" in Sigma, "moving" and
// for RP the line in E, for PR the line in Sigma: "line_point", "line_direction"), "first_pose"
// (the coupler pose the links are drawn at), "coupler_curve" and its panel's "view"; a linkage
// drawn by its joints (six-bars) has, instead of the dyads, "joints": {"bodies" (each body's
// joint indices, ground first), "task_body", "names", "at_first_pose" (places in Sigma)}.
// Non-finite points are left out (null for a dyad's unused point).
std::string PictureToJson(const Picture& picture);

// A spherical motion result's picture (model "spherical"): one panel per listed four-bar, its
// geometry on the unit sphere about the centre (points are unit vectors along Sigma's axes).
struct SphericalPanel {
  std::string title;                // e.g. "1: spherical 4R, crank-rocker"
  std::vector<std::string> labels;  // defects, pose error
  // The viewer's direction of the panel's orthographic view: along the mean of the four-bar's
  // axes at the first pose (Sigma's z-axis drawn up where it can be).
  Eigen::Vector3d toward = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d fixed_axes[2];  // the ground pivots: input, output
  Eigen::Vector3d pins[2];        // the moving axes at the first pose's (nearer) assembly
  // Polylines of the sphere: the great-circle arcs of the ground, the input and output links and
  // the coupler at the first pose; the coupler's arc at every task pose; the crank pins' paths
  // over the circuit.
  std::vector<Eigen::Vector3d> ground, input_link, output_link, coupler;
  std::vector<std::vector<Eigen::Vector3d>> task_couplers;
  std::vector<Eigen::Vector3d> input_pin_path, output_pin_path;
};

struct SphericalPicture {
  std::string title;                                 // the task (file name)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // the motion's centre, in Sigma
  std::vector<SphericalPanel> panels;                // ranked order; none without a four-bar
};

// The picture of a spherical motion result (model "spherical"): its listed four-bars in ranked
// order, at most `max_panels`. Nothing for another result.
std::optional<SphericalPicture> SphericalTaskPicture(const std::string& title, const Task& task,
                                                     const SpatialMotionResult& result,
                                                     size_t max_panels);

// The SVG of a spherical picture: each panel an orthographic view of the unit sphere about the
// centre along its `toward` (Sigma's axes from the centre, the ground pivots, the links at the
// first pose, the crank pins' paths, the coupler arc at every task pose; the far hemisphere
// dashed), or the bare sphere when no four-bar is listed.
std::string RenderSphericalSvg(const SphericalPicture& picture);

// The spherical picture's geometry as JSON, for drawing elsewhere (linkfit.plot), projected as
// the SVG projects it: "kind": "spherical", "title", "heading" (what the SVG's heading says after
// the title), "center" and "mechanisms", each with "title", "labels", its view's basis "toward",
// "right" and "up" (unit vectors of Sigma: a point x of the sphere is drawn at (x . right,
// x . up), y up, on the near hemisphere when x . toward >= 0), "sigma_axes" (Sigma's unit axes so
// drawn), the polylines "ground", "input_link", "output_link", "coupler", "input_pin_path",
// "output_pin_path" and "task_couplers" (a list of polylines) as runs {"front": on the near
// hemisphere, "points": [[x, y], ...]} (the SVG's solid and dashed pieces), and "fixed_pivots"
// and "pins" (input, output), each {"at": [x, y], "front"}.
std::string SphericalPictureToJson(const SphericalPicture& picture);

// The JSON of a solved task's picture, whichever it is (PictureToJson of TaskPicture, or
// SphericalPictureToJson of SphericalTaskPicture); empty with the reason in *why when there is
// none (a spatial platform).
std::string TaskPictureJson(const std::string& title, const Task& task, const TaskResult& result,
                            size_t max_panels, std::string* why);

// A standalone SVG document (one panel per mechanism, in a grid).
std::string RenderSvg(const Picture& picture);

// An animation of mechanism `index` through its cycle: an SVG with SMIL animation, or an HTML
// page (html = true) that animates the same drawing with a few lines of script.
std::string RenderAnimation(const Picture& picture, size_t index, bool html);

}  // namespace linkfit

#endif  // LINKFIT_APPS_PICTURE_H_
