// The Python module's native part, linkfit._linkfit (python/linkfit/__init__.py wraps it): a task
// as JSON text in, the result as JSON text out, exactly as `linkfit solve` writes it; bad input
// raises linkfit.InputError with the CLI's one-line message. The GIL is released while solving
// and refining; solve_many takes it back every 50 ms, so Ctrl-C stops a batch.
#include <glog/logging.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "apps/cad_export.h"
#include "apps/picture.h"
#include "lib/analysis_io.h"
#include "lib/parallel.h"
#include "lib/result_io.h"
#include "lib/result_summary.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"

namespace py = pybind11;

namespace linkfit {
namespace {

// A solved task: the result's JSON text, and what its picture is drawn from (apps/picture.h
// TaskPictureJson, the SVG's content), made only when asked (linkfit.plot): it costs about as much
// as a five-pose solve.
struct Drawn {
  std::string result;
  Task task;
  TaskResult solved;

  // The picture's JSON text (planar or spherical), or empty with the reason (a spatial platform)
  // in *why.
  std::string Picture(std::string* why) const {
    constexpr size_t kPanels = 12;  // as `linkfit solve --svg`
    return TaskPictureJson("", task, solved, kPanels, why);
  }
};

Drawn WithPicture(const Task& task, TaskResult result) {
  Drawn drawn;
  drawn.result = ResultToJson(result, 2);
  drawn.task = task;
  drawn.solved = std::move(result);
  return drawn;
}

Drawn SolveDrawn(const std::string& text, const std::string& source) {
  const Task task = ParseTask(text, source);
  return WithPicture(task, SolveTask(task));
}

// Every task on `threads` threads (0: the machine's), results in input order. Every task is
// read and validated first, so bad input in any task raises InputError for the first such task
// (by position) before anything is solved. Called with the GIL held; it is released while the
// tasks are read and solved, and taken back every 50 ms to let Python handle signals: on Ctrl-C
// (or any signal handler that raises) no further task is started, those being solved finish,
// and the handler's exception (KeyboardInterrupt) is raised.
std::vector<std::string> SolveMany(const std::vector<std::string>& texts,
                                   const std::vector<std::string>& sources, int threads) {
  const size_t count = texts.size();
  const unsigned jobs = ThreadCount(threads);
  std::vector<Task> tasks(count);
  std::vector<std::string> results(count);
  std::vector<std::exception_ptr> errors(count);
  std::atomic<bool> stop(false);
  // Runs work(i) for every task on the pool while this thread waits for signals.
  const auto run = [&](const auto& work) {
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    std::thread runner;
    {
      py::gil_scoped_release release;
      runner = std::thread([&]() {
        ParallelFor(count, jobs, [&](size_t i) {
          if (stop.load()) return;
          try {
            work(i);
          } catch (...) {
            errors[i] = std::current_exception();
          }
        });
        std::lock_guard<std::mutex> lock(mutex);
        done = true;
        finished.notify_all();
      });
    }
    while (true) {
      {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(mutex);
        if (finished.wait_for(lock, std::chrono::milliseconds(50), [&]() { return done; })) break;
      }
      if (PyErr_CheckSignals() != 0) {
        stop.store(true);
        {
          py::gil_scoped_release release;
          runner.join();
        }
        throw py::error_already_set();
      }
    }
    runner.join();
    for (const std::exception_ptr& error : errors) {
      if (error) std::rethrow_exception(error);
    }
  };
  run([&](size_t i) { tasks[i] = ParseTask(texts[i], sources[i]); });
  // A task a thread: each solve on one (TaskSolverOptions::threads) when the pool has more.
  TaskSolverOptions solver;
  solver.threads = jobs > 1 ? 1 : 0;
  run([&](size_t i) { results[i] = ResultToJson(SolveTask(tasks[i], solver), 2); });
  return results;
}

// One design refined against one task (as `linkfit refine` does), `mechanism` counted from 0.
Drawn RefineDrawn(const std::string& task_text, const std::string& design_text, int mechanism) {
  const Task task = ParseTask(task_text, "task");
  const TaskDesign design = ParseTaskDesign(design_text, "design", task);
  RefineChoice choice;
  choice.mechanism = mechanism;
  choice.mechanism_item = "design: mechanism=" + std::to_string(mechanism);
  return WithPicture(task, RefineTask(task, design, choice));
}

}  // namespace
}  // namespace linkfit

PYBIND11_MODULE(_linkfit, m) {
  m.doc() = "linkfit's native solver (use the linkfit package, not this module)";
  // The project's version (CMakeLists.txt), as `linkfit --version` prints it.
  m.attr("__version__") = LINKFIT_VERSION;
  // Ceres reports through glog at ERROR level on steps the refiners handle; the CLI silences it
  // the same way (apps/cli.cc RunCli).
  FLAGS_minloglevel = google::GLOG_FATAL;
  py::register_exception<linkfit::InputError>(m, "InputError", PyExc_ValueError);
  py::class_<linkfit::Drawn>(m, "Drawn")
      .def_readonly("result", &linkfit::Drawn::result)
      .def(
          "picture",
          [](const linkfit::Drawn& drawn) {
            std::string why;
            std::string picture;
            {
              py::gil_scoped_release release;
              picture = drawn.Picture(&why);
            }
            return py::make_tuple(picture, why);
          },
          "The picture's JSON text and, when there is none, why.");
  m.def(
      "solve_drawn_json",
      [](const std::string& text, const std::string& source) {
        py::gil_scoped_release release;
        return linkfit::SolveDrawn(text, source);
      },
      py::arg("text"), py::arg("source") = "task",
      "Solves one task given as JSON text; the result's JSON text and its picture's.");
  m.def(
      "refine_drawn_json",
      [](const std::string& task, const std::string& design, int mechanism) {
        py::gil_scoped_release release;
        return linkfit::RefineDrawn(task, design, mechanism);
      },
      py::arg("task"), py::arg("design"), py::arg("mechanism") = 0,
      "Refines a design (JSON text) against a task (JSON text); the result's JSON text and its "
      "picture's.");
  m.def(
      "solve_many_json",
      [](const std::vector<std::string>& texts, const std::vector<std::string>& sources,
         int threads) { return linkfit::SolveMany(texts, sources, threads); },
      py::arg("texts"), py::arg("sources"), py::arg("threads") = 0,
      "Solves tasks (JSON texts) on `threads` threads (0: all cores); results in input order.");
  m.def(
      "analyze_json",
      [](const std::string& result, int mechanism, double input_speed, int steps, double force_x,
         double force_y, double output_torque, double slider_force,
         std::optional<std::pair<double, double>> range_deg, const std::vector<double>& masses,
         const std::string& length_unit, bool gravity, const std::string& range_kind,
         const std::string& task) {
        linkfit::AnalysisRequest request;
        request.mechanism = mechanism;
        request.input_speed = input_speed;
        request.steps = steps;
        request.load.coupler_force = Eigen::Vector2d(force_x, force_y);
        request.load.output_torque = output_torque;
        request.load.slider_force = slider_force;
        request.range_deg = range_deg;
        request.mass_list = masses;
        request.masses.gravity = gravity;
        request.length_unit = length_unit;
        request.task_range = range_kind == "task";
        request.whole_range = range_kind == "whole";
        std::optional<linkfit::Task> parsed;
        if (!task.empty()) {
          parsed = linkfit::ParseTask(task, "task");
          request.task = &*parsed;
        }
        py::gil_scoped_release release;
        return linkfit::AnalyzeResultText(result, "result", request);
      },
      py::arg("result"), py::arg("mechanism") = 0, py::arg("input_speed") = 1.0,
      py::arg("steps") = 360, py::arg("force_x") = 0.0, py::arg("force_y") = 0.0,
      py::arg("output_torque") = 0.0, py::arg("slider_force") = 0.0,
      py::arg("range_deg") = std::nullopt, py::arg("masses") = std::vector<double>{},
      py::arg("length_unit") = "", py::arg("gravity") = false, py::arg("range_kind") = "",
      py::arg("task") = "",
      "The kinematics of one mechanism of a result (JSON text), as `linkfit analyze` writes it.");
  m.def(
      "export_json",
      [](const std::string& result, int mechanism, std::optional<double> input_deg,
         const std::string& task, bool svg) {
        linkfit::CadExportRequest request;
        request.mechanism = mechanism;
        request.input_deg = input_deg;
        std::optional<linkfit::Task> parsed;
        if (!task.empty()) {
          parsed = linkfit::ParseTask(task, "task");
          request.task = &*parsed;
        }
        py::gil_scoped_release release;
        return py::bytes(svg ? linkfit::ResultSvg(result, "result", request)
                             : linkfit::ResultDxf(result, "result", request));
      },
      py::arg("result"), py::arg("mechanism") = 0, py::arg("input_deg") = std::nullopt,
      py::arg("task") = "", py::arg("svg") = false,
      "One mechanism of a result (JSON text) as DXF (or, with `svg`, SVG) text, as `linkfit "
      "export` writes it.");
  m.def(
      "summary_json",
      [](const std::string& result, const std::string& title) {
        try {
          return linkfit::ResultSummary(result, title);
        } catch (const std::invalid_argument& error) {
          throw linkfit::InputError(std::string("result: ") + error.what());
        }
      },
      py::arg("result"), py::arg("title") = "",
      "The summary table of a result (JSON text), as `linkfit show` prints it.");
}
