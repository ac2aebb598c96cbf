// Solves a task file with the installed library and prints the result as `linkfit solve` would.
#include <fstream>
#include <iostream>
#include <sstream>

#include "lib/result_io.h"
#include "lib/task_io.h"
#include "optimizers/task_solver.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: consumer TASK.json\n";
    return 2;
  }
  std::ifstream file(argv[1]);
  std::stringstream text;
  text << file.rdbuf();
  const linkfit::Task task = linkfit::ParseTask(text.str(), argv[1]);
  std::cout << linkfit::ResultToJson(linkfit::SolveTask(task), 2) << "\n";
  return 0;
}
