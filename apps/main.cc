// Entry point of the `linkfit` program; everything happens in RunCli (cli.h).
#include "apps/cli.h"

int main(int argc, char** argv) { return linkfit::RunCli(argc, argv); }
