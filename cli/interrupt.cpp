#include <csignal>

#include "cli/commands.h"

namespace meshtour::cli {
namespace {
volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_signal(int) { g_interrupted = 1; }
}  // namespace

void install_interrupt_handlers() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

void throw_if_interrupted() {
  if (g_interrupted) throw Interrupted();
}

}  // namespace meshtour::cli
