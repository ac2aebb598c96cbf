// The load benchmark of `linkfit serve` (issue 38): starts `linkfit serve --port 0` and sends it
// five-pose tasks of random four-bars (printed to 8 digits, as a page sends them) from 200
// clients at once, each on its own keep-alive connection as a browser holds one (all driven by
// one poll loop, so that the clients leave the two cores to the server):
//   burst       every client sends one request at the same instant, `rounds` times;
//   burst+slow  the same while a slow request (a thorough untimed path of ten points, in its own
//               process) runs;
//   sustained   every client sends requests back to back for `seconds`.
// A request is lost when it fails, answers other than 200, or its result lists other dyads than
// the library's own solve of the same task. Prints each scenario's requests, losses and latency
// (median, 99th percentile, worst, from the request's start to its whole reply).
//   linkfit_serve_load [--linkfit PATH] [--clients 200] [--rounds 10] [--seconds 5] [--seed 38]
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/percentile.h"
#include "lib/result_io.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"
#include "tests/support/random_mechanism.h"
#include "tests/support/rounded_task.h"
// After the project's headers: <resolv.h>, which httplib.h includes, defines a macro (_res) that
// would rewrite a parameter name of Eigen's.
#include <httplib.h>  // NOLINT(build/include_order)

extern char** environ;

namespace linkfit {
namespace {

using Clock = std::chrono::steady_clock;

// `linkfit serve --port 0` as a child; its URL's port read from its first line.
struct Server {
  pid_t pid = 0;
  int port = 0;
};

Server StartServer(const std::string& program) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  std::vector<std::string> args = {program, "serve", "--port", "0", "--threads", "256"};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  Server server;
  if (::posix_spawn(&server.pid, program.c_str(), &actions, nullptr, argv.data(), environ) != 0) {
    throw std::runtime_error("cannot run " + program);
  }
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  std::string line;
  char c = 0;
  while (::read(fds[0], &c, 1) == 1 && c != '\n') line += c;
  ::close(fds[0]);
  const size_t colon = line.rfind(':');
  if (line.rfind("linkfit serve: http://", 0) != 0 || colon == std::string::npos) {
    throw std::runtime_error("the server did not start: '" + line + "'");
  }
  server.port = std::stoi(line.substr(colon + 1));
  return server;
}

// The server's own CPU time in seconds (user and system; not its children's: the slow solve).
double ServerCpuSeconds(const Server& server) {
  std::ifstream file("/proc/" + std::to_string(server.pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string field;
  double ticks = 0;
  for (int k = 3; k <= 15 && fields >> field; ++k) {
    if (k >= 14) ticks += std::stod(field);  // utime, stime
  }
  return ticks / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

void StopServer(const Server& server) {
  ::kill(server.pid, SIGINT);
  int status = 0;
  ::waitpid(server.pid, &status, 0);
}

double OwnCpuSeconds() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// A task, and the dyads the library finds for it (what each reply must list).
struct LoadTask {
  std::string text;
  std::string dyads;
};

std::vector<LoadTask> MakeTasks(size_t count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<LoadTask> tasks;
  TaskSolverOptions solver;
  solver.threads = 1;
  std::vector<double> parse_us, solve_us, json_us;
  const auto us_since = [](Clock::time_point start) {
    return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  };
  while (tasks.size() < count) {
    const testing::GeneratedTask generated = testing::RandomFourBarTask(rng);
    LoadTask task;
    task.text = testing::PlanarMotionText(generated.poses, 8);
    auto start = Clock::now();
    const Task parsed = ParseTask(task.text, "load");
    parse_us.push_back(us_since(start));
    start = Clock::now();
    const TaskResult solved = SolveTask(parsed, solver);
    solve_us.push_back(us_since(start));
    start = Clock::now();
    const std::string result = ResultToJson(solved, -1);
    json_us.push_back(us_since(start));
    task.dyads = nlohmann::json::parse(result)["dyads"].dump();
    tasks.push_back(task);
  }
  std::printf(
      "one request's work in one thread (median of %zu): parse %.0f us, solve %.0f us, "
      "result JSON %.0f us\n",
      count, Percentile(parse_us, 0.5), Percentile(solve_us, 0.5), Percentile(json_us, 0.5));
  return tasks;
}

struct Outcome {
  std::vector<double> ms;
  size_t lost = 0;
};

// One request: its task, latency and reply, judged after the run.
struct Sent {
  const LoadTask* task = nullptr;
  int round = 0;  // the burst's round (0: on new connections)
  double ms = 0.0;
  int status = -1;
  std::string body;
};

// A client's keep-alive connection, driven by one poll loop with every other: the 200 clients
// cost one thread, so the server has the cores (a thread a client would take a third of them)
// and a burst's requests leave at once.
class Connection {
 public:
  explicit Connection(int port) : host_("127.0.0.1:" + std::to_string(port)) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const int yes = 1;
    // As browsers do: else a request's body waits for the server's delayed acknowledgement.
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof(yes));
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
      throw std::runtime_error("cannot connect to the server");
    }
    ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
  }
  ~Connection() { ::close(fd_); }
  int fd() const { return fd_; }
  bool busy() const { return busy_; }
  bool wants_write() const { return written_ < out_.size(); }

  void Start(const LoadTask& task, int round) {
    out_ = "POST /api/solve HTTP/1.1\r\nHost: " + host_ +
           "\r\nContent-Type: application/json\r\n"
           "Content-Length: " +
           std::to_string(task.text.size()) + "\r\n\r\n" + task.text;
    written_ = 0;
    in_.clear();
    sent_ = Sent();
    sent_.task = &task;
    sent_.round = round;
    start_ = Clock::now();
    busy_ = true;
    Write();
  }
  void Write() {
    while (written_ < out_.size()) {
      const ssize_t n = ::send(fd_, out_.data() + written_, out_.size() - written_, MSG_NOSIGNAL);
      if (n <= 0) return;
      written_ += static_cast<size_t>(n);
    }
  }
  // Reads what has come; true when the reply is whole (then in *done).
  bool Read(Sent* done) {
    char buffer[1 << 16];
    while (true) {
      const ssize_t n = ::recv(fd_, buffer, sizeof(buffer), 0);
      if (n > 0) {
        in_.append(buffer, static_cast<size_t>(n));
        continue;
      }
      if (n == 0) return Finish(done, "the server closed the connection");
      break;
    }
    const size_t head = in_.find("\r\n\r\n");
    if (head == std::string::npos) return false;
    const size_t length_at = in_.find("Content-Length: ");
    if (length_at == std::string::npos || length_at > head) return Finish(done, "no length");
    const size_t length = std::stoul(in_.substr(length_at + 16));
    if (in_.size() < head + 4 + length) return false;
    sent_.status = std::stoi(in_.substr(9, 3));
    sent_.body = in_.substr(head + 4, length);
    return Finish(done, nullptr);
  }

  // Gives up on the reply: lost.
  void Abandon(Sent* done) { Finish(done, "no reply within 60 s"); }

 private:
  bool Finish(Sent* done, const char* error) {
    sent_.ms = std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
    if (error != nullptr) sent_.body = error;
    *done = std::move(sent_);
    busy_ = false;
    return true;
  }

  int fd_ = -1;
  std::string host_;
  std::string out_, in_;
  size_t written_ = 0;
  bool busy_ = false;
  Sent sent_;
  Clock::time_point start_;
};

// The latencies, and the replies lost: failed, not 200, or other dyads than the library's; of
// the rounds from `first_round` on.
Outcome Judge(const std::vector<Sent>& sent, int first_round = 0, int last_round = 1 << 30) {
  Outcome outcome;
  for (const Sent& one : sent) {
    if (one.round < first_round || one.round > last_round) continue;
    outcome.ms.push_back(one.ms);
    bool right = one.status == 200;
    if (right) {
      try {
        right = nlohmann::json::parse(one.body)["dyads"].dump() == one.task->dyads;
      } catch (const std::exception&) {
        right = false;
      }
    }
    if (!right && ++outcome.lost <= 3) {
      std::fprintf(stderr, "lost: %d %s\n", one.status, one.body.substr(0, 200).c_str());
    }
  }
  return outcome;
}

// `clients` connections; round r: each sends task (r * clients + i) at once, and the round ends
// when every reply is in. With `seconds` > 0 instead: each sends its next request as soon as
// its reply is in, until then.
std::vector<Sent> Run(int port, const std::vector<LoadTask>& tasks, int clients, int rounds,
                      double seconds) {
  std::vector<std::unique_ptr<Connection>> connections;
  for (int i = 0; i < clients; ++i) connections.push_back(std::make_unique<Connection>(port));
  std::vector<Sent> sent;
  const auto stop_at = Clock::now() + std::chrono::milliseconds(static_cast<int>(seconds * 1000));
  size_t next = 0;
  const auto wait_all = [&](bool again) {
    std::vector<pollfd> polled(connections.size());
    // A server that stops answering loses what it holds, and the run goes on.
    const auto give_up_at = std::max(Clock::now(), stop_at) + std::chrono::seconds(60);
    while (true) {
      if (Clock::now() > give_up_at) {
        for (auto& c : connections) {
          if (!c->busy()) continue;
          Sent lost;
          c->Abandon(&lost);
          sent.push_back(std::move(lost));
        }
        return;
      }
      size_t busy = 0;
      for (size_t i = 0; i < connections.size(); ++i) {
        const Connection& c = *connections[i];
        polled[i] = pollfd{
            c.fd(), static_cast<short>(c.busy() ? (c.wants_write() ? POLLOUT : 0) | POLLIN : 0), 0};
        busy += c.busy();
      }
      if (busy == 0) return;
      ::poll(polled.data(), polled.size(), 1000);
      for (size_t i = 0; i < connections.size(); ++i) {
        Connection& c = *connections[i];
        if (!c.busy() || polled[i].revents == 0) continue;
        if (polled[i].revents & POLLOUT) c.Write();
        Sent done;
        if ((polled[i].revents & (POLLIN | POLLHUP | POLLERR)) && c.Read(&done)) {
          sent.push_back(std::move(done));
          if (again && Clock::now() < stop_at) c.Start(tasks[next++ % tasks.size()], 0);
        }
      }
    }
  };
  if (seconds > 0) {
    for (auto& c : connections) c->Start(tasks[next++ % tasks.size()], 0);
    wait_all(true);
    return sent;
  }
  for (int r = 0; r < rounds; ++r) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the previous round settles
    for (int i = 0; i < clients; ++i) {
      connections[i]->Start(tasks[(static_cast<size_t>(r) * clients + i) % tasks.size()], r);
    }
    wait_all(false);
  }
  return sent;
}

void Print(const char* name, const Outcome& outcome, double seconds) {
  std::printf("%-14s %9zu %6zu %9.2f %9.2f %9.2f", name, outcome.ms.size(), outcome.lost,
              Percentile(outcome.ms, 0.5), Percentile(outcome.ms, 0.99),
              Percentile(outcome.ms, 1.0));
  if (seconds > 0) std::printf(" %9.0f", outcome.ms.size() / seconds);
  std::printf("\n");
  std::fflush(stdout);
}

int Main(int argc, char** argv) {
  std::string program = (std::filesystem::path(argv[0]).parent_path() / "linkfit").string();
  int clients = 200, rounds = 10;
  double seconds = 5.0;
  uint64_t seed = 38;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--linkfit" && has_value) {
      program = argv[++i];
    } else if (arg == "--clients" && has_value) {
      clients = std::stoi(argv[++i]);
    } else if (arg == "--rounds" && has_value) {
      rounds = std::stoi(argv[++i]);
    } else if (arg == "--seconds" && has_value) {
      seconds = std::stod(argv[++i]);
    } else if (arg == "--seed" && has_value) {
      seed = std::stoull(argv[++i]);
    } else {
      std::fprintf(stderr,
                   "usage: linkfit_serve_load [--linkfit PATH] [--clients N] [--rounds N] "
                   "[--seconds S] [--seed N]\n");
      return 2;
    }
  }
  const std::vector<LoadTask> tasks = MakeTasks(static_cast<size_t>(clients) * rounds, seed);
  const Server server = StartServer(program);
  // Stopped however this ends (an exception, a lost connection): never left running.
  struct StopAtEnd {
    const Server& server;
    bool stopped = false;
    ~StopAtEnd() {
      if (!stopped) StopServer(server);
    }
  } stop_at_end{server};
  const double client_cpu_before = OwnCpuSeconds();
  size_t requests = 0;
  std::printf(
      "linkfit serve under load: %d clients, each on its own keep-alive connection; %u "
      "cores\n",
      clients, std::thread::hardware_concurrency());
  std::printf("%-14s %9s %6s %9s %9s %9s %9s\n", "scenario", "requests", "lost", "p50 ms", "p99 ms",
              "max ms", "req/s");
  const std::vector<Sent> bursts = Run(server.port, tasks, clients, rounds, 0);
  requests += bursts.size();
  // The first burst opens the connections; the others find them open, as a page's are.
  Print("burst, new", Judge(bursts, 0, 0), 0);
  Print("burst", Judge(bursts, 1), 0);
  // The slow request: a thorough untimed path, solved in its own process meanwhile.
  std::string slow_task;
  {
    std::ifstream file(std::filesystem::path(LINKFIT_SOURCE_DIR) / "data" /
                       "classic_path_ellipse_10_points.json");
    std::stringstream text;
    text << file.rdbuf();
    slow_task = text.str();
  }
  std::atomic<bool> slow_done(false);
  double slow_ms = 0;
  int slow_status = 0;
  // Joined however this ends (an exception unwinding waits for its reply, then stops the server).
  struct Joined {
    std::thread thread;
    ~Joined() {
      if (thread.joinable()) thread.join();
    }
  };
  Joined slow{std::thread([&] {
    httplib::Client client("127.0.0.1", server.port);
    client.set_read_timeout(300);
    client.set_tcp_nodelay(true);
    const auto start = Clock::now();
    const httplib::Result reply =
        client.Post("/api/solve?effort=thorough", slow_task, "application/json");
    slow_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    slow_status = reply ? reply->status : -1;
    slow_done = true;
  })};
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const Outcome with_slow = Judge(Run(server.port, tasks, clients, rounds, 0), 1);
  const bool slow_still_running = !slow_done;
  requests += with_slow.ms.size() + clients;
  Print("burst+slow", with_slow, 0);
  slow.thread.join();
  std::printf("  the slow request (thorough, 10 untimed points): %d in %.0f ms, %s\n", slow_status,
              slow_ms, slow_still_running ? "still running when the burst ended" : "ended first");
  const Outcome sustained = Judge(Run(server.port, tasks, clients, 0, seconds));
  requests += sustained.ms.size();
  Print("sustained", sustained, seconds);
  const double client_cpu = OwnCpuSeconds() - client_cpu_before;
  const double server_cpu = ServerCpuSeconds(server);
  StopServer(server);
  stop_at_end.stopped = true;
  std::printf(
      "CPU per request: server %.0f us (its children's, the slow solve, not counted), "
      "clients %.0f us\n",
      1e6 * server_cpu / requests, 1e6 * client_cpu / requests);
  return 0;
}

}  // namespace
}  // namespace linkfit

int main(int argc, char** argv) {
  try {
    return linkfit::Main(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "linkfit_serve_load: %s\n", error.what());
    return 1;
  }
}
