#include "interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include "libbrdf/image_file.h"

namespace brdf_cli {

namespace {
std::atomic<bool> published{false};

// The signals to take: SIGINT, SIGTERM, SIGHUP, except those the caller set to be ignored (nohup
// ignores SIGHUP, a shell's background job SIGINT): an ignored signal stays ignored.
sigset_t handled_signals() {
  sigset_t set;
  sigemptyset(&set);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (sigaction(signal_number, nullptr, &current) == 0 && current.sa_handler != SIG_IGN) sigaddset(&set, signal_number);
  }
  return set;
}

[[noreturn]] void wait_for_signal(sigset_t set, std::string command) {
  int signal_number = 0;
  while (sigwait(&set, &signal_number) != 0) {
  }
  libbrdf::PublicationLock lock;  // no rename is in progress from here on
  lock.remove_temporaries();
  // Every command publishes its outputs once (one file, or one group): counted under the lock, so
  // a signal right after the rename is not reported as "no file written".
  const bool complete = published.load() || lock.publications() > 0;
  const char* name = signal_number == SIGINT ? "SIGINT" : signal_number == SIGTERM ? "SIGTERM" : "SIGHUP";
  const std::string message = "brdf: " + command + " interrupted (" + name + "); " +
                              (complete ? "the output files were already complete" : "no file written") + "\n";
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, message.data(), message.size());
  ::_exit(128 + signal_number);
}
}  // namespace

void handle_interrupts(const char* command) {
  static std::atomic<bool> installed{false};
  if (installed.exchange(true)) return;  // once per process (main.cpp calls it first thing)
  const sigset_t set = handled_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(wait_for_signal, set, std::string(command)).detach();
}

void outputs_published() { published.store(true); }

}  // namespace brdf_cli
