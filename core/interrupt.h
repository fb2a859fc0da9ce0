#pragma once
// Ctrl-C and SIGTERM (a farm's time limit): long commands make the signals set a flag, and every
// long loop of every stage checks it, so that the job stops within moments and the destructors
// on the way out remove partial outputs; the program then exits with 130. A watchdog ends the
// process the same way where a library call cannot be stopped.
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <exception>
#include <mutex>
#include <set>
#include <string>
#include <thread>

namespace meshtour {

/// Thrown by throw_if_interrupted() after SIGINT or SIGTERM.
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted"; }
};

namespace detail {
inline volatile std::sig_atomic_t interrupt_flag = 0;
inline void on_interrupt_signal(int) { interrupt_flag = 1; }

/// The temporaries of outputs being written (PendingFile registers them), for the watchdog to
/// remove when it has to end the process. Allocated once and never freed, so that it outlives
/// every static destructor that may run while the watchdog acts.
struct Temporaries {
  std::mutex mutex;
  std::set<std::string> paths;
};
inline Temporaries& temporaries() {
  static Temporaries* registry = new Temporaries;
  return *registry;
}

/// How long a stage may take to notice the flag before the watchdog ends the process.
inline constexpr std::chrono::milliseconds kInterruptGrace{500};

// Some stages run inside libraries that cannot be asked to stop (OpenMesh's reader, Eigen's sparse
// solver): a second after Ctrl-C they may still be busy. The watchdog gives every stage the grace
// above to stop by itself (the normal path: destructors remove partial outputs, exit 130), then
// removes the registered temporaries itself and ends the process with 130.
inline void watch_for_interrupt() {
  while (!interrupt_flag) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(kInterruptGrace);
  {
    std::lock_guard lock(temporaries().mutex);
    for (const std::string& path : temporaries().paths) ::unlink(path.c_str());
  }
  static constexpr char kMessage[] = "meshtour: interrupted; partial outputs removed\n";
  [[maybe_unused]] const auto written = ::write(2, kMessage, sizeof kMessage - 1);
  ::_exit(130);
}
}  // namespace detail

/// Makes SIGINT/SIGTERM set the flag instead of killing the process, and starts the watchdog
/// that ends the process (exit 130, temporaries removed) if no stage has stopped it in time.
inline void install_interrupt_handlers() {
  std::signal(SIGINT, detail::on_interrupt_signal);
  std::signal(SIGTERM, detail::on_interrupt_signal);
  static const bool watching = [] {
    std::thread(detail::watch_for_interrupt).detach();
    return true;
  }();
  (void)watching;
}

/// Registers a temporary output file for the watchdog to remove (PendingFile does this).
inline void register_temporary(const std::string& path) {
  std::lock_guard lock(detail::temporaries().mutex);
  detail::temporaries().paths.insert(path);
}
/// The temporary is gone (renamed or removed): the watchdog must not touch its name any more.
inline void unregister_temporary(const std::string& path) {
  std::lock_guard lock(detail::temporaries().mutex);
  detail::temporaries().paths.erase(path);
}

/// True once a handled signal has arrived (for callbacks that cannot throw, such as Embree's
/// build-progress monitor, which cancels the build by returning false).
inline bool interrupt_requested() { return detail::interrupt_flag != 0; }

/// Throws Interrupted once a handled signal has arrived.
inline void throw_if_interrupted() {
  if (detail::interrupt_flag) throw Interrupted();
}

}  // namespace meshtour
