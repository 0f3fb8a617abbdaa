#include "slipfit/pipeline/cli.h"

#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  return slipfit::pipeline::runCommandLine(args, std::cout, std::cerr);
}
