// SPDX-License-Identifier: MIT
#include "interrupt.hpp"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <thread>

#include "sonarsynth/formats/io/atomic_file.hpp"

namespace sonarsynth::cli {

void install_interrupt_cleanup() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  if (pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) return;
  try {
    std::thread([set] {
      int sig = 0;
      while (sigwait(&set, &sig) != 0) {
      }
      remove_pending_temporaries();
      static const char kMsg[] = "sonarsynth: interrupted; partial output removed\n";
      (void)!::write(STDERR_FILENO, kMsg, sizeof kMsg - 1);
      ::_exit(128 + sig);
    }).detach();
  } catch (...) {
    // No thread for the cleanup: restore the default behaviour rather than ignore the signals.
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  }
}

}  // namespace sonarsynth::cli
