// The routes of `linkfit serve` (web_api.h): the CLI's steps, with query parameters for its
// options and the request's parts for its files.
#include "apps/web_api.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <future>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "apps/analysis_svg.h"
#include "apps/cad_export.h"
#include "apps/child_process.h"
#include "lib/analysis_io.h"
#include "lib/result_io.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"

namespace linkfit {
namespace {

constexpr long long kMaxIndex = 1000000000;
constexpr long long kMaxCurvePoints = 100000;
// Cancels of solves not (yet) running remembered, the newest.
constexpr size_t kCancelledEarlyKept = 256;

std::string Shown(const std::string& text) { return ShownInMessage(text); }

// The query parameters of a route: only those it takes, each at most once.
class Params {
 public:
  Params(const WebRequest& request, const char* route, std::set<std::string> known)
      : request_(request) {
    for (const auto& [name, value] : request.params) {
      if (known.count(name) == 0) {
        std::string names;
        for (const std::string& k : known) names += (names.empty() ? "" : ", ") + k;
        throw InputError("?" + Shown(name) + ": not a parameter of " + route +
                         (names.empty() ? " (it takes none)" : " (it takes " + names + ")"));
      }
      if (request.params.count(name) > 1) throw InputError("?" + Shown(name) + ": given twice");
    }
  }
  std::optional<std::string> Text(const std::string& name) const {
    const auto found = request_.params.find(name);
    if (found == request_.params.end()) return std::nullopt;
    return found->second;
  }
  long long Whole(const std::string& name, long long minimum, long long maximum,
                  long long fallback) const {
    const std::optional<std::string> text = Text(name);
    if (!text) return fallback;
    size_t used = 0;
    long long value = 0;
    try {
      value = std::stoll(*text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text->size() || value < minimum || value > maximum) {
      throw InputError("?" + name + ": expected a whole number from " + std::to_string(minimum) +
                       " to " + std::to_string(maximum) + ", got '" + Shown(*text) + "'");
    }
    return value;
  }
  std::vector<double> Numbers(const std::string& name, size_t fewest, size_t most) const {
    std::vector<double> values;
    const std::string text = Text(name).value_or("");
    size_t start = 0;
    while (start <= text.size()) {
      const size_t comma = std::min(text.find(',', start), text.size());
      const std::string item = text.substr(start, comma - start);
      size_t used = 0;
      double value = 0.0;
      try {
        value = std::stod(item, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != item.size() || !std::isfinite(value)) {
        throw InputError("?" + name + ": expected a number, got '" + Shown(item) + "'");
      }
      values.push_back(value);
      start = comma + 1;
    }
    if (values.size() < fewest || values.size() > most) {
      throw InputError("?" + name + ": expected " + std::to_string(fewest) +
                       (most > fewest ? " to " + std::to_string(most) : "") +
                       " numbers separated by commas, got " + std::to_string(values.size()));
    }
    return values;
  }
  std::optional<double> Number(const std::string& name) const {
    if (!Text(name)) return std::nullopt;
    return Numbers(name, 1, 1)[0];
  }
  bool Flag(const std::string& name) const {
    const std::optional<std::string> text = Text(name);
    if (!text) return false;
    if (*text == "1" || *text == "true" || text->empty()) return true;
    if (*text == "0" || *text == "false") return false;
    throw InputError("?" + name + ": expected 1 or 0 (true or false), got '" + Shown(*text) + "'");
  }
  std::string OneOf(const std::string& name, const std::vector<std::string>& choices) const {
    const std::optional<std::string> text = Text(name);
    if (!text) return choices[0];
    if (std::find(choices.begin(), choices.end(), *text) != choices.end()) return *text;
    std::string names;
    for (const std::string& c : choices) names += (names.empty() ? "" : ", ") + c;
    throw InputError("?" + name + ": expected one of " + names + ", got '" + Shown(*text) + "'");
  }

 private:
  const WebRequest& request_;
};

// The text of part `name`: a JSON file's content. A solve takes its task as the plain body too.
const std::string& Part(const WebRequest& request, const std::string& name, const char* route,
                        bool required = true) {
  static const std::string kNone;
  const auto found = request.parts.find(name);
  if (found == request.parts.end()) {
    if (!required) return kNone;
    const char* what = name == "task"     ? "the task file"
                       : name == "design" ? "a result, or a design written by hand"
                                          : "the result file";
    throw InputError(std::string(route) + ": expected a multipart/form-data part '" + name +
                     "' (the JSON of " + what + ")");
  }
  if (found->second.find_first_not_of(" \t\r\n") == std::string::npos) {
    throw InputError(name + ": empty, expected JSON");
  }
  return found->second;
}

// What the routes on a result take: the result, its task when given, and the rank of the
// mechanism (?mechanism, counted from 1) as an index.
struct OnResult {
  const std::string& result_text;
  std::optional<Task> task;
  int mechanism = 0;
};

OnResult ReadOnResult(const WebRequest& request, const Params& params, const char* route) {
  OnResult on{Part(request, "result", route), std::nullopt, 0};
  const std::string& task_text = Part(request, "task", route, false);
  if (!task_text.empty()) on.task = ParseTask(task_text, "task");
  on.mechanism = static_cast<int>(params.Whole("mechanism", 1, kMaxIndex, 1) - 1);
  return on;
}

// A route's reply, its errors as replies: bad input 400 with the CLI's line, anything else 500.
template <typename Route>
WebReply Guarded(const Route& route) {
  try {
    return route();
  } catch (const InputError& error) {
    return ErrorReply(400, error.what());
  } catch (const std::exception& error) {
    return ErrorReply(500, std::string("internal error: ") + error.what());
  }
}

// Exact planar motion (at most five poses, a four-bar): microseconds to a few milliseconds,
// bounded by the task's size, so it runs in the request's thread; everything else may search
// for seconds and runs in a child process with a time limit.
bool IsLive(const Task& task) {
  return task.problem == ProblemKind::kMotion && task.space == Space::kPlanar && !task.six_bar &&
         task.planar_poses.size() <= 5;
}

// The last line of a child's standard error without "linkfit: error: ", the pipes it read
// named as the request's parts.
std::string ChildMessage(const std::string& err) {
  std::string line = err;
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  line =
      line.substr(line.find_last_of('\n') == std::string::npos ? 0 : line.find_last_of('\n') + 1);
  for (const char* prefix : {"linkfit: error: ", "linkfit: "}) {
    if (line.rfind(prefix, 0) == 0) {
      line = line.substr(std::string(prefix).size());
      break;
    }
  }
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"/dev/stdin", "task"},
                                 {"/dev/fd/3", "design"},
                                 {"--mechanism", "?mechanism"}}) {
    for (size_t at = line.find(from); at != std::string::npos; at = line.find(from, at)) {
      line.replace(at, from.size(), to);
    }
  }
  return line;
}

}  // namespace

std::string ShownInMessage(const std::string& text) {
  std::string shown = text.substr(0, 40);
  for (char& c : shown) {
    if (c < 0x20 || c >= 0x7f) c = '?';
  }
  return shown.size() < text.size() ? shown + "..." : shown;
}

WebReply ErrorReply(int status, const std::string& message) {
  WebReply reply;
  reply.status = status;
  reply.body = nlohmann::json{{"error", message}}.dump() + "\n";
  return reply;
}

WebApi::WebApi(WebApiOptions options) : options_(std::move(options)) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned k = 0; k < cores; ++k) {
    live_workers_.emplace_back([this] {
      while (true) {
        std::function<void()> work;
        {
          std::unique_lock<std::mutex> lock(live_mutex_);
          live_ready_.wait(lock, [this] { return stopping_ || !live_queue_.empty(); });
          if (live_queue_.empty()) return;
          work = std::move(live_queue_.front());
          live_queue_.pop_front();
        }
        work();
      }
    });
  }
  if (options_.long_solves <= 0) {
    options_.long_solves = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }
}

WebApi::~WebApi() {
  {
    std::lock_guard<std::mutex> lock(live_mutex_);
    stopping_ = true;
  }
  live_ready_.notify_all();
  for (std::thread& worker : live_workers_) worker.join();
}

WebReply WebApi::OnLiveWorker(const std::function<WebReply()>& work) {
  std::promise<WebReply> reply;
  std::future<WebReply> done = reply.get_future();
  {
    std::lock_guard<std::mutex> lock(live_mutex_);
    live_queue_.emplace_back([&work, &reply] { reply.set_value(work()); });
  }
  live_ready_.notify_one();
  return done.get();
}

WebReply WebApi::Cancel(const WebRequest& request) {
  return Guarded([&] {
    const Params params(request, "cancel", {"request_id"});
    const std::optional<std::string> id = params.Text("request_id");
    if (!id || id->empty()) throw InputError("cancel: expected ?request_id=, the solve's");
    bool found = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = cancels_.find(*id);
      if (it != cancels_.end()) {
        it->second->store(true);
        found = true;
      } else {
        // Not here yet (its request still uploading or parsing): refused when it comes.
        cancelled_early_.push_back(*id);
        if (cancelled_early_.size() > kCancelledEarlyKept) cancelled_early_.pop_front();
      }
    }
    turn_.notify_all();
    WebReply reply;
    reply.body = nlohmann::json{{"cancelled", found}}.dump() + "\n";
    return reply;
  });
}

void WebApi::StopLongSolves() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_long_ = true;
    for (std::atomic<bool>* flag : every_long_) flag->store(true);
  }
  turn_.notify_all();
}

WebReply WebApi::Version() const {
  WebReply reply;
  reply.body = nlohmann::json{{"version", LINKFIT_VERSION},
                              {"limits",
                               {{"max_request_bytes", options_.max_request_bytes},
                                {"solve_time_limit_s", options_.solve_time_limit_s},
                                {"long_solves", options_.long_solves},
                                {"max_steps", options_.max_steps}}}}
                   .dump() +
               "\n";
  return reply;
}

WebReply WebApi::RunLong(const std::vector<std::string>& args,
                         const std::map<int, std::string>& inputs, const std::string& request_id) {
  const auto cancel = std::make_shared<std::atomic<bool>>(false);
  bool ran = false;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (stopping_long_) return ErrorReply(503, "the server is stopping");
    if (running_ >= options_.long_solves && waiting_ >= options_.max_waiting) {
      return ErrorReply(503, "busy: " + std::to_string(running_) + " long solves running and " +
                                 std::to_string(waiting_) + " waiting; try again later");
    }
    if (!request_id.empty()) {
      if (cancels_.count(request_id) > 0) {
        throw InputError("?request_id=" + Shown(request_id) + ": already in use");
      }
      // Cancelled before it got here (its cancel overtook it on another connection).
      if (std::find(cancelled_early_.begin(), cancelled_early_.end(), request_id) !=
          cancelled_early_.end()) {
        return ErrorReply(409, "cancelled (/api/cancel) before it started");
      }
      cancels_[request_id] = cancel;
    }
    every_long_.insert(cancel.get());
    ++waiting_;
    turn_.wait(lock, [&] { return running_ < options_.long_solves || cancel->load(); });
    --waiting_;
    // Decided once, under the lock: a cancel after this point stops the child instead.
    ran = !cancel->load();
    if (ran) ++running_;
  }
  struct Turn {
    WebApi* api;
    const std::string& id;
    std::atomic<bool>* flag;
    bool ran;
    ~Turn() {
      std::lock_guard<std::mutex> lock(api->mutex_);
      if (ran) --api->running_;
      if (!id.empty()) api->cancels_.erase(id);
      api->every_long_.erase(flag);
      api->turn_.notify_all();
    }
  } turn{this, request_id, cancel.get(), ran};
  if (!ran) {
    return stopping_long_ ? ErrorReply(503, "the server is stopping")
                          : ErrorReply(409, "cancelled (/api/cancel) before it started");
  }
  ChildRun run;
  run.program = options_.program;
  run.args = args;
  run.inputs = inputs;
  run.time_limit_s = options_.solve_time_limit_s;
  run.cancel = cancel.get();
  ChildOutcome outcome = RunChild(run);
  if (outcome.cancelled) {
    return stopping_long_ ? ErrorReply(503, "the server is stopping")
                          : ErrorReply(409, "cancelled (/api/cancel)");
  }
  if (outcome.timed_out) {
    char limit[32];
    std::snprintf(limit, sizeof(limit), "%g", options_.solve_time_limit_s);
    return ErrorReply(503, std::string("time limit: the ") + args[0] +
                               " passed the server's limit of " + limit +
                               " s and was stopped; choose a lower effort or fewer poses or "
                               "points, or run `linkfit " +
                               args[0] + "` on the command line");
  }
  if (outcome.output_too_long) return ErrorReply(500, "internal error: the result is too large");
  if (outcome.exit_status == 0) {
    WebReply reply;
    reply.body = std::move(outcome.out);
    return reply;
  }
  const std::string message = ChildMessage(outcome.err);
  if (outcome.exit_status == 2) return ErrorReply(400, message);
  return ErrorReply(500, message.empty() ? "internal error: the solver stopped" : message);
}

WebReply WebApi::Solve(const WebRequest& request) {
  const std::string& text =
      request.parts.count("task") > 0 ? request.parts.at("task") : request.body;
  // Parsed on a live worker, and solved there when it is live; else solved in a child process
  // from this thread (`long_args`).
  std::vector<std::string> long_args;
  WebReply reply = OnLiveWorker([&] {
    return Guarded([&] {
      const Params params(request, "solve", {"effort", "curve_points", "request_id"});
      if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
        throw InputError("task: empty request body, expected a task (the JSON of a task file)");
      }
      Task task = ParseTask(text, "task");
      const std::optional<std::string> effort = params.Text("effort");
      if (effort) params.OneOf("effort", {"fast", "balanced", "thorough"});
      const long long curve_points =
          params.Whole("curve_points", 2, kMaxCurvePoints, kDefaultCurvePoints);
      if (!IsLive(task)) {
        long_args = {"solve", "/dev/stdin", "--curve-points", std::to_string(curve_points)};
        if (effort) long_args.insert(long_args.end(), {"--effort", *effort});
        return WebReply();
      }
      if (effort) task.effort = *EffortOfName(*effort);
      TaskSolverOptions solver;
      solver.threads = 1;  // the other workers solve other requests meanwhile
      TaskResult result = SolveTask(task, solver);
      if (auto* planar = std::get_if<PlanarMotionResult>(&result)) {
        planar->curve_points = static_cast<int>(curve_points);
      }
      WebReply live;
      live.body = ResultToJson(result, -1) + "\n";
      return live;
    });
  });
  if (long_args.empty()) return reply;
  const auto id = request.params.find("request_id");
  return Guarded([&] {
    return RunLong(long_args, {{0, text}}, id == request.params.end() ? std::string() : id->second);
  });
}

WebReply WebApi::Refine(const WebRequest& request) {
  return Guarded([&] {
    const Params params(request, "refine", {"mechanism", "request_id"});
    const std::string& task_text = Part(request, "task", "refine");
    const std::string& design_text = Part(request, "design", "refine");
    // Checked here, so a bad request is named as the CLI names it before any process starts.
    const Task task = ParseTask(task_text, "task");
    ParseTaskDesign(design_text, "design", task);
    const long long mechanism = params.Whole("mechanism", 1, kMaxIndex, 1);
    return RunLong({"refine", "/dev/stdin", "/dev/fd/3", "--mechanism", std::to_string(mechanism)},
                   {{0, task_text}, {3, design_text}}, params.Text("request_id").value_or(""));
  });
}

WebReply WebApi::Analyze(const WebRequest& request) {
  return Guarded([&] {
    const Params params(request, "analyze",
                        {"mechanism", "steps", "range", "input_speed", "force", "output_torque",
                         "slider_force", "mass", "length_unit", "gravity", "format"});
    const OnResult on = ReadOnResult(request, params, "analyze");
    AnalysisRequest analysis;
    analysis.task = on.task ? &*on.task : nullptr;
    analysis.mechanism = on.mechanism;
    analysis.steps = static_cast<int>(params.Whole("steps", 1, options_.max_steps, 360));
    if (params.Text("range")) SetAnalysisRange(*params.Text("range"), "?range", &analysis);
    analysis.input_speed = params.Number("input_speed").value_or(1.0);
    if (params.Text("force")) {
      const std::vector<double> force = params.Numbers("force", 2, 2);
      analysis.load.coupler_force = Eigen::Vector2d(force[0], force[1]);
    }
    analysis.load.output_torque = params.Number("output_torque").value_or(0.0);
    analysis.load.slider_force = params.Number("slider_force").value_or(0.0);
    if (params.Text("mass")) analysis.mass_list = params.Numbers("mass", 3, 5);
    analysis.length_unit = params.Text("length_unit").value_or("");
    analysis.masses.gravity = params.Flag("gravity");
    const std::string format = params.OneOf("format", {"json", "csv", "svg"});
    analysis.csv = format == "csv";
    const std::string text = AnalyzeResultText(on.result_text, "result", analysis);
    WebReply reply;
    if (format == "svg") {
      reply.content_type = "image/svg+xml";
      reply.body = AnalysisSvg(text);
      reply.filename = "analysis.svg";
    } else {
      reply.body = text;
      if (format == "csv") {
        reply.content_type = "text/csv";
        reply.filename = "analysis.csv";
      }
    }
    return reply;
  });
}

WebReply WebApi::Export(const WebRequest& request) {
  return Guarded([&] {
    const Params params(request, "export", {"mechanism", "format", "input_deg"});
    const OnResult on = ReadOnResult(request, params, "export");
    CadExportRequest drawing;
    drawing.task = on.task ? &*on.task : nullptr;
    drawing.mechanism = on.mechanism;
    drawing.input_deg = params.Number("input_deg");
    const std::string format = params.OneOf("format", {"dxf", "svg"});
    WebReply reply;
    if (format == "dxf") {
      reply.content_type = "application/dxf";
      reply.body = ResultDxf(on.result_text, "result", drawing);
      reply.filename = "mechanism.dxf";
    } else {
      reply.content_type = "image/svg+xml";
      reply.body = ResultSvg(on.result_text, "result", drawing);
      reply.filename = "mechanism.svg";
    }
    return reply;
  });
}

}  // namespace linkfit
