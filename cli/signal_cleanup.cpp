#include "signal_cleanup.hpp"

#include <signal.h>

#include "granular/grid_io.hpp"

namespace granular::cli {

namespace {

/// Async-signal-safe: unlink() through remove_pending_temporaries, then the default action.
extern "C" void remove_temporaries_and_reraise(int sig) {
  granular::remove_pending_temporaries();
  struct sigaction fallback {};
  fallback.sa_handler = SIG_DFL;
  sigemptyset(&fallback.sa_mask);
  sigaction(sig, &fallback, nullptr);
  raise(sig);  // delivered with the default action once this handler returns
}

}  // namespace

void install_signal_cleanup() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ}) {
    struct sigaction old {};
    if (sigaction(sig, nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&action.sa_mask);
    sigaction(sig, &action, nullptr);
  }
}

}  // namespace granular::cli
