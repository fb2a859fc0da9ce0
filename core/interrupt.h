#pragma once
// Ctrl-C and SIGTERM (a farm's time limit): long commands make the signals set a flag, and every
// long loop of every stage checks it, so that the job stops within moments and the destructors
// on the way out remove partial outputs; the program then exits with 130.
#include <csignal>
#include <exception>

namespace meshtour {

/// Thrown by throw_if_interrupted() after SIGINT or SIGTERM.
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

namespace detail {
inline volatile std::sig_atomic_t interrupt_flag = 0;
inline void on_interrupt_signal(int) { interrupt_flag = 1; }
}  // namespace detail

/// Makes SIGINT/SIGTERM set the flag instead of killing the process.
inline void install_interrupt_handlers() {
  std::signal(SIGINT, detail::on_interrupt_signal);
  std::signal(SIGTERM, detail::on_interrupt_signal);
}

/// Throws Interrupted once a handled signal has arrived.
inline void throw_if_interrupted() {
  if (detail::interrupt_flag) throw Interrupted();
}

}  // namespace meshtour
