#pragma once

/// The signals that stop a run, in one place (async-signal-safe handlers only):
/// - SIGUSR1 (what mpirun forwards and SLURM's --signal sends before a time limit): a stop
///   request; the run writes a checkpoint at the next step and exits with code 3.
/// - SIGINT, SIGTERM, SIGHUP (Ctrl-C, kill, scancel, SLURM's time limit without --signal,
///   preemption): while a run that can checkpoint is armed, the first one is a stop request as
///   well (the run exits with 128 + the signal's number after its checkpoint); a second one, or
///   one when nothing is armed, removes the output locks (the registered cleanup) and ends the
///   process with the signal's default action.
namespace ringdem {

/// Installs the SIGUSR1 handler; idempotent.
void install_stop_signal_handler();
/// Whether this process received a stop request (SIGUSR1, or an armed SIGINT/SIGTERM/SIGHUP).
bool stop_signal_received();
/// The terminating signal (SIGINT, SIGTERM, SIGHUP) that requested the stop, 0 if none did.
int terminating_signal();
/// This process's stop request as a code for the ranks' reduction (Simulation::request_stop):
/// 0 none, kStopRequested for SIGUSR1 (or a wall-time limit, which the caller adds), 1 + the
/// signal's number for a terminating signal, so that the largest code is the one to report.
inline constexpr int kStopRequested = 1;
int stop_request_code();
/// After the ranks agreed on the largest code: the stop becomes this process's too, as if the
/// signal had been sent to all (a sweep starts no further case; a terminating signal that
/// another rank received sets this one's exit code and message).
void adopt_agreed_stop(int code);
/// "SIGINT", "SIGTERM", "SIGHUP", "SIGUSR1", or "a signal".
const char* signal_name(int sig);
/// For tests: forget a received signal.
void reset_stop_signal();

/// While one lives (and was made with `arm` true), the first SIGINT, SIGTERM or SIGHUP requests
/// a checkpointed stop instead of ending the process: RunControl holds one for a run that can
/// checkpoint. Installs the handlers.
class TerminatingSignalsArmed {
 public:
  explicit TerminatingSignalsArmed(bool arm);
  ~TerminatingSignalsArmed();
  TerminatingSignalsArmed(const TerminatingSignalsArmed&) = delete;
  TerminatingSignalsArmed& operator=(const TerminatingSignalsArmed&) = delete;

 private:
  bool armed_ = false;
};

/// What a terminating signal that ends the process runs first: `cleanup` must be
/// async-signal-safe (OutputLock unlinks its files). Installs the handlers; signals that are
/// ignored (nohup) or handled by someone else stay as they are.
void set_termination_cleanup(void (*cleanup)());

}  // namespace ringdem
