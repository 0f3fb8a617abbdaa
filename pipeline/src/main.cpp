#include "slipfit/pipeline/cli.h"

#include "interrupt_cleanup.h"

#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  // Ctrl-C or a kill during a run removes the temporary outputs (exit 130 / 143).
  slipfit::pipeline::detail::installInterruptCleanup();
  const std::vector<std::string> args(argv + 1, argv + argc);
  return slipfit::pipeline::runCommandLine(args, std::cout, std::cerr);
}
