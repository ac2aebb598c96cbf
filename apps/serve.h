// `linkfit serve`: a local HTTP server (cpp-httplib, Debian's libcpp-httplib-dev) for the
// interactive designer: the single-page app of web/ (installed to share/linkfit/web) and the JSON
// API of apps/web_api.h. Binds to loopback unless told otherwise; requests are limited in size
// (413 beyond) and long solves in time (apps/web_api.h).
#ifndef LINKFIT_APPS_SERVE_H_
#define LINKFIT_APPS_SERVE_H_

#include <cstddef>
#include <string>

namespace linkfit {

struct ServeOptions {
  std::string host = "127.0.0.1";
  int port = 8765;                             // 0: any free port (the URL printed says which)
  std::string web_dir;                         // the page's files (default: found, see .cc)
  size_t max_request_bytes = size_t{8} << 20;  // a request's body at most
  double solve_time_limit_s = 120;             // a long solve's limit
  int threads = 256;                           // connections served at once
  int long_solves = 0;                         // long solves at a time (0: the cores)
};

// Serves until interrupted (SIGINT, SIGTERM). Prints "linkfit serve: http://HOST:PORT/" on the
// first line of stdout once listening. Throws InputError when it cannot listen or finds no page.
int RunServe(const ServeOptions& options);

}  // namespace linkfit

#endif  // LINKFIT_APPS_SERVE_H_
