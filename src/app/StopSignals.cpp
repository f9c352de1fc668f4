#include "app/StopSignals.hpp"

#include <array>
#include <csignal>

namespace ringdem {

namespace {

constexpr std::array<int, 3> kTerminatingSignals{SIGINT, SIGTERM, SIGHUP};

volatile std::sig_atomic_t g_stop_requested = 0;
volatile std::sig_atomic_t g_terminating_signal = 0;
volatile std::sig_atomic_t g_armed = 0;
void (*volatile g_cleanup)() = nullptr;

extern "C" void on_stop_signal(int) {
  g_stop_requested = 1;
}

extern "C" void on_terminating_signal(int sig) {
  // The first one while armed: a stop request, like SIGUSR1. A second one, or one while nothing
  // can checkpoint: the locks go and the process ends as the signal's default would end it.
  if (g_armed && g_terminating_signal == 0) {
    g_terminating_signal = sig;
    g_stop_requested = 1;
    return;
  }
  if (g_cleanup != nullptr) g_cleanup();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_terminating_handlers() {
  static bool installed = false;
  if (installed) return;
  installed = true;
  for (int sig : kTerminatingSignals) {
    struct sigaction old {};
    sigaction(sig, nullptr, &old);
    // Leave alone a handler someone else installed, or an ignored signal (nohup's SIGHUP).
    if (old.sa_handler != SIG_DFL) continue;
    struct sigaction action {};
    action.sa_handler = on_terminating_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(sig, &action, nullptr);
  }
}

}  // namespace

void install_stop_signal_handler() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGUSR1, &action, nullptr);
}

bool stop_signal_received() {
  return g_stop_requested != 0;
}

int terminating_signal() {
  return g_terminating_signal;
}

int stop_request_code() {
  if (g_terminating_signal != 0) return 1 + g_terminating_signal;
  return g_stop_requested != 0 ? kStopRequested : 0;
}

void adopt_agreed_stop(int code) {
  if (code <= 0) return;
  g_stop_requested = 1;
  if (code > kStopRequested && g_terminating_signal == 0) g_terminating_signal = code - 1;
}

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    case SIGUSR1:
      return "SIGUSR1";
    default:
      return "a signal";
  }
}

void reset_stop_signal() {
  g_stop_requested = 0;
  g_terminating_signal = 0;
}

TerminatingSignalsArmed::TerminatingSignalsArmed(bool arm) : armed_(arm) {
  if (!armed_) return;
  install_terminating_handlers();
  g_armed = 1;
}

TerminatingSignalsArmed::~TerminatingSignalsArmed() {
  if (armed_) g_armed = 0;
}

void set_termination_cleanup(void (*cleanup)()) {
  g_cleanup = cleanup;
  install_terminating_handlers();
}

}  // namespace ringdem
