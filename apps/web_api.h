// The JSON API of `linkfit serve` (apps/serve.h), independent of HTTP: each route takes a request
// (its body, its multipart parts, its query parameters) and gives a reply (status, type, body).
// The bodies are the CLI's task, design and result JSON; the query parameters are the CLI's
// options. Bad input answers 400 with the CLI's one-line message (the parts named "task",
// "design" and "result" where the CLI names files).
//   POST /api/solve    body: a task; ?effort=, &curve_points=  -> the result (as `linkfit solve`)
//   POST /api/refine   parts task, design; ?mechanism=         -> the result (`linkfit refine`)
//   POST /api/analyze  parts result [, task]; ?mechanism=, steps, range, input_speed, force,
//                      output_torque, slider_force, mass, length_unit, gravity, format=json|csv|svg
//   POST /api/export   parts result [, task]; ?mechanism=, format=dxf|svg, input_deg
//   POST /api/cancel   ?request_id=: stops the solve or refinement sent with that request_id
//   GET  /api/version  the version and the server's limits
// Planar motion through at most five poses (exact, microseconds: what the page recomputes while a
// pose is dragged), analyses and drawings run in the request's thread. Every other solve and every
// refinement runs in a child `linkfit` process (apps/child_process.h), at most `long_solves` at a
// time, killed at `solve_time_limit_s`: a long solve neither stalls the others nor outlives its
// limit.
#ifndef LINKFIT_APPS_WEB_API_H_
#define LINKFIT_APPS_WEB_API_H_

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace linkfit {

struct WebApiOptions {
  std::string program;              // the `linkfit` executable long solves run in
  double solve_time_limit_s = 120;  // a long solve's or refinement's limit
  int long_solves = 0;              // long solves at a time (0: the machine's cores)
  int max_waiting = 64;             // long solves waiting for their turn; more answer 503
  int max_steps = 20000;            // an analysis's samples at most
  size_t max_request_bytes = size_t{8} << 20;  // reported by /api/version (the server enforces it)
};

struct WebRequest {
  std::string body;                                // a plain body (solve)
  std::map<std::string, std::string> parts;        // multipart/form-data parts by name
  std::multimap<std::string, std::string> params;  // query parameters
};

struct WebReply {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::string filename;  // a download's name (Content-Disposition), when set
};

// `text` (a query parameter, a path) as a message shows it: at most 40 printable characters.
std::string ShownInMessage(const std::string& text);

// The message of an error reply: {"error": message}.
WebReply ErrorReply(int status, const std::string& message);

class WebApi {
 public:
  explicit WebApi(WebApiOptions options);
  ~WebApi();
  WebApi(const WebApi&) = delete;
  WebApi& operator=(const WebApi&) = delete;

  WebReply Solve(const WebRequest& request);
  WebReply Refine(const WebRequest& request);
  WebReply Analyze(const WebRequest& request);
  WebReply Export(const WebRequest& request);
  WebReply Cancel(const WebRequest& request);
  WebReply Version() const;
  // Stops every long solve, waiting or running (503 "the server is stopping"), and refuses new
  // ones: the server's shutdown.
  void StopLongSolves();

  const WebApiOptions& options() const { return options_; }

 private:
  // Runs `linkfit args...` with `inputs` on its descriptors (0: stdin, 3: /dev/fd/3) in its turn
  // among the long solves; its result JSON, or the error reply its failure calls for.
  // `request_id` (may be empty) names it for Cancel.
  WebReply RunLong(const std::vector<std::string>& args, const std::map<int, std::string>& inputs,
                   const std::string& request_id);

  // Runs `work` on one of the live workers and waits for it.
  WebReply OnLiveWorker(const std::function<WebReply()>& work);

  WebApiOptions options_;
  // The live solves (parsed, solved and written) run on one worker thread a core, in the order
  // they came: more at once would only share the cores in smaller slices, so every request of
  // a burst would finish late (the last no sooner); and the same few threads keep their memory
  // allocator's caches warm, where the server's many connection threads would contend for it.
  std::vector<std::thread> live_workers_;
  std::deque<std::function<void()>> live_queue_;
  std::mutex live_mutex_;
  std::condition_variable live_ready_;
  bool stopping_ = false;
  std::mutex mutex_;
  std::condition_variable turn_;
  int running_ = 0;
  int waiting_ = 0;
  // The long solves waiting or running by their request_id, each with its cancel flag; every
  // long solve's flag (with a request_id or not); request_ids cancelled before their solve came.
  std::map<std::string, std::shared_ptr<std::atomic<bool>>> cancels_;
  std::set<std::atomic<bool>*> every_long_;
  std::deque<std::string> cancelled_early_;
  std::atomic<bool> stopping_long_{false};
};

}  // namespace linkfit

#endif  // LINKFIT_APPS_WEB_API_H_
