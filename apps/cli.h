// The `linkfit` command line: parses arguments, reads and validates the task file, calls the
// solver and writes the result. Exit status 0: solved (possibly with no solution, said in the
// result's notes); 1: internal fault; 2: bad input or usage, one line on stderr, no output.
#ifndef LINKFIT_APPS_CLI_H_
#define LINKFIT_APPS_CLI_H_

namespace linkfit {

// Runs the program as `main` would and returns its exit status.
int RunCli(int argc, char** argv);

}  // namespace linkfit

#endif  // LINKFIT_APPS_CLI_H_
