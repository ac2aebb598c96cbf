// `linkfit serve` (serve.h): httplib's server, its thread pool, limits and static files around
// the routes of apps/web_api.h.
#include "apps/serve.h"

#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <thread>
#include <utility>

#include "apps/web_api.h"
#include "lib/task_io.h"
// After the project's headers: httplib.h brings <resolv.h>, whose macro _res would rewrite a
// parameter name of Eigen's (included through lib/task_io.h) into an expression.
#include <httplib.h>  // NOLINT(build/include_order)

namespace linkfit {
namespace {

// The server the signal handlers stop (one per process).
std::atomic<httplib::Server*> running_server{nullptr};

// The first signal stops the server (the requests being served end first); a second ends the
// program at once.
std::atomic<int> signals_seen{0};
void StopOnSignal(int signal) {
  if (signals_seen++ > 0) ::_exit(128 + signal);
  if (httplib::Server* server = running_server.load()) server->stop();
}

// This program's own path: long solves run in it (`linkfit solve`, `linkfit refine`).
std::string ThisProgram() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("cannot find the linkfit program (/proc/self/exe)");
  return self.string();
}

// The page's files: --web-dir, else those installed beside this program (<prefix>/bin/linkfit
// serves <prefix>/share/linkfit/web, whatever the prefix), else the source tree's (a build's
// program).
std::string WebDirectory(const ServeOptions& options, const std::string& program) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!options.web_dir.empty()) {
    if (!fs::is_regular_file(fs::path(options.web_dir) / "index.html", error)) {
      throw InputError("--web-dir " + options.web_dir + ": no index.html there");
    }
    return options.web_dir;
  }
  const std::string installed =
      (fs::path(program).parent_path().parent_path() / "share" / "linkfit" / "web").string();
  for (const std::string& dir : {installed, std::string(LINKFIT_WEB_SOURCE)}) {
    if (fs::is_regular_file(fs::path(dir) / "index.html", error)) return dir;
  }
  throw InputError("serve: the page's files are missing (looked in " + installed + " and " +
                   LINKFIT_WEB_SOURCE + "); reinstall linkfit or give --web-dir");
}

bool IsLoopback(const std::string& host) {
  return host == "127.0.0.1" || host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

// The request in web_api's terms: its body, its multipart parts, its query parameters.
WebRequest ToWebRequest(const httplib::Request& request) {
  WebRequest web;
  if (request.is_multipart_form_data()) {
    for (const auto& [name, part] : request.files) web.parts[name] = part.content;
  } else {
    web.body = request.body;
  }
  // The query's parameters only: httplib adds a form-encoded body's fields to request.params, and
  // `curl -d @task.json` sends a task as a form.
  const size_t query = request.target.find('?');
  httplib::Params params;
  if (query != std::string::npos)
    httplib::detail::parse_query_text(request.target.substr(query + 1), params);
  for (const auto& [name, value] : params) web.params.emplace(name, value);
  return web;
}

void Send(WebReply reply, httplib::Response& response) {
  response.status = reply.status;
  if (!reply.filename.empty()) {
    response.set_header("Content-Disposition", "attachment; filename=\"" + reply.filename + "\"");
  }
  response.set_header("Cache-Control", "no-store");
  response.body = std::move(reply.body);
  response.set_header("Content-Type", reply.content_type);
}

}  // namespace

int RunServe(const ServeOptions& options) {
  const std::string program = ThisProgram();
  const std::string web_dir = WebDirectory(options, program);
  WebApiOptions api_options;
  api_options.program = program;
  api_options.solve_time_limit_s = options.solve_time_limit_s;
  api_options.long_solves = options.long_solves;
  api_options.max_request_bytes = options.max_request_bytes;
  WebApi api(api_options);

  httplib::Server server;
  const size_t threads = static_cast<size_t>(options.threads);
  server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  server.set_payload_max_length(options.max_request_bytes);
  // httplib writes a reply's headers and body apart: with Nagle's algorithm the body waits for
  // the client's delayed acknowledgement (40 ms) on every request of a kept-alive connection.
  server.set_tcp_nodelay(true);
  // A browser keeps its connections open: short, so idle ones give their thread back.
  server.set_keep_alive_timeout(2);
  // ... but many requests each: a dragged pose sends one a frame.
  server.set_keep_alive_max_count(1000);
  server.set_read_timeout(10);
  server.set_write_timeout(10);
  server.set_file_extension_and_mimetype_mapping("js", "text/javascript");
  server.set_file_extension_and_mimetype_mapping("mjs", "text/javascript");
  server.set_file_extension_and_mimetype_mapping("svg", "image/svg+xml");
  server.set_file_extension_and_mimetype_mapping("json", "application/json");
  // No compression: Debian's httplib compresses what a browser accepts with Brotli at its best
  // (slowest) quality, 50 ms for the page's script and 8 ms for a five-pose result, all of it
  // latency on a loopback connection, where the bytes cost nothing. The request is httplib's own
  // (non-const) object, handed on as const.
  //
  // On loopback, only this machine's pages: a request whose Host is not the server's own address
  // comes through a name an attacker's page rebound to 127.0.0.1 (DNS rebinding), and a POST
  // from another site's page (its Origin, or Sec-Fetch-Site: cross-site) would spend the cores
  // on its solves. Both answer 403; curl and scripts send neither header.
  int port = options.port;
  const bool loopback = IsLoopback(options.host);
  server.set_pre_routing_handler([&port, loopback](const httplib::Request& request,
                                                   httplib::Response& response) {
    const_cast<httplib::Request&>(request).headers.erase("Accept-Encoding");
    if (!loopback) return httplib::Server::HandlerResponse::Unhandled;
    const std::string host = request.get_header_value("Host");
    const std::string suffix = ":" + std::to_string(port);
    bool own = false;
    for (const char* name : {"127.0.0.1", "localhost", "[::1]"}) {
      own |= host == name || host == name + suffix;  // a loopback name, its port or none
    }
    std::string refusal;
    if (!own) {
      refusal = "Host " + ShownInMessage(host) + ": this server answers to 127.0.0.1" + suffix +
                " and localhost" + suffix + " only";
    } else if (request.method == "POST") {
      const std::string origin = request.get_header_value("Origin");
      if ((!origin.empty() && origin != "http://" + host) ||
          request.get_header_value("Sec-Fetch-Site") == "cross-site") {
        refusal =
            "Origin " + ShownInMessage(origin) + ": another site's page may not use this server";
      }
    }
    if (refusal.empty()) return httplib::Server::HandlerResponse::Unhandled;
    Send(ErrorReply(403, refusal), response);
    return httplib::Server::HandlerResponse::Handled;
  });
  if (!server.set_mount_point("/", web_dir)) {
    throw InputError("serve: cannot serve the page's files from " + web_dir);
  }
  const auto route = [&server](const char* path, auto handler) {
    server.Post(path, [handler](const httplib::Request& request, httplib::Response& response) {
      Send(handler(ToWebRequest(request)), response);
    });
  };
  route("/api/solve", [&api](const WebRequest& r) { return api.Solve(r); });
  route("/api/refine", [&api](const WebRequest& r) { return api.Refine(r); });
  route("/api/analyze", [&api](const WebRequest& r) { return api.Analyze(r); });
  route("/api/export", [&api](const WebRequest& r) { return api.Export(r); });
  route("/api/cancel", [&api](const WebRequest& r) { return api.Cancel(r); });
  server.Get("/api/version", [&api](const httplib::Request&, httplib::Response& response) {
    Send(api.Version(), response);
  });
  // A route called with the other method: 405, with the one it takes.
  const auto wrong_method = [](const char* allowed) {
    return [allowed](const httplib::Request& request, httplib::Response& response) {
      Send(ErrorReply(405, ShownInMessage(request.path) + ": use " + allowed), response);
      response.set_header("Allow", allowed);
    };
  };
  for (const char* path :
       {"/api/solve", "/api/refine", "/api/analyze", "/api/export", "/api/cancel"}) {
    server.Get(path, wrong_method("POST"));
  }
  server.Post("/api/version", wrong_method("GET"));
  // httplib's own refusals (413 too large, 404 no such file or route, 400 malformed) get the
  // API's JSON body.
  server.set_error_handler(
      [&options](const httplib::Request& request, httplib::Response& response) {
        if (!response.body.empty()) return;
        std::string message;
        if (response.status == 413) {
          message = "request too large: the server takes at most " +
                    std::to_string(options.max_request_bytes) + " bytes (--max-request-bytes)";
        } else if (response.status == 404) {
          message = request.path.rfind("/api/", 0) == 0
                        ? request.path +
                              ": no such route (solve, refine, analyze, export, cancel: "
                              "POST; version: GET)"
                        : ShownInMessage(request.path) + ": not found";
        } else {
          message = "HTTP " + std::to_string(response.status);
        }
        Send(ErrorReply(response.status, message), response);
      });
  server.set_exception_handler(
      [](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
        std::string message = "internal error";
        try {
          if (error) std::rethrow_exception(error);
        } catch (const std::exception& e) {
          message += std::string(": ") + e.what();
        } catch (...) {
        }
        Send(ErrorReply(500, message), response);
      });

  // The listening socket: SO_REUSEADDR (a restarted server gets its port back at once) but not
  // httplib's default SO_REUSEPORT, under which a second server on the same port would share it
  // instead of being told that it is in use; and kept, for its backlog below.
  std::atomic<int> listening{-1};
  server.set_socket_options([&listening](socket_t socket) {
    const int yes = 1;
    ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    listening = socket;
  });
  if (port == 0) {
    port = server.bind_to_any_port(options.host);
    if (port < 0) throw InputError("--host " + options.host + ": cannot listen there");
  } else if (!server.bind_to_port(options.host, port)) {
    throw InputError("--port " + std::to_string(port) + ": cannot listen on " + options.host + ":" +
                     std::to_string(port) + " (in use by another program?)");
  }
  // httplib listens with a backlog of 5: connections beyond it are dropped and retried by the
  // client a second later. Listening again sets the backlog for a page's and many clients' bursts.
  if (listening >= 0) ::listen(listening, SOMAXCONN);
  if (!IsLoopback(options.host)) {
    std::cerr << "linkfit serve: listening on " << options.host
              << ", not only loopback: anyone who can reach it can run solves" << std::endl;
  }
  // A client gone mid-reply must not end the server (SIGPIPE); Ctrl-C and SIGTERM stop it.
  ::signal(SIGPIPE, SIG_IGN);
  running_server = &server;
  ::signal(SIGINT, StopOnSignal);
  ::signal(SIGTERM, StopOnSignal);
  const std::string shown_host =
      options.host.find(':') != std::string::npos ? "[" + options.host + "]" : options.host;
  std::cout << "linkfit serve: http://" << shown_host << ":" << port << "/" << std::endl;
  // The first signal stops the server: its long solves are stopped at once (a thread of their
  // own, for a signal handler may not lock), so that the connections' threads end.
  std::atomic<bool> served{false};
  std::thread stopper([&] {
    while (!served && signals_seen == 0) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    api.StopLongSolves();
  });
  server.listen_after_bind();
  served = true;
  stopper.join();
  running_server = nullptr;
  return 0;
}

}  // namespace linkfit
