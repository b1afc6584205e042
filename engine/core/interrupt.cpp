#include "engine/core/interrupt.hpp"

#include <csignal>

namespace granflow {

namespace {
std::atomic<bool> interrupt_flag{false};
std::atomic<int> interrupt_signal{0};
using Handler = void (*)(int);
Handler previous_int = SIG_DFL;
Handler previous_term = SIG_DFL;

extern "C" void on_signal(int signal_number) {
  interrupt_signal.store(signal_number);
  interrupt_flag.store(true);
  // The next signal of this kind ends the process as it would have.
  std::signal(signal_number, SIG_DFL);
}
}  // namespace

InterruptGuard::InterruptGuard() {
  interrupt_flag.store(false);
  interrupt_signal.store(0);
  previous_int = std::signal(SIGINT, on_signal);
  previous_term = std::signal(SIGTERM, on_signal);
}

InterruptGuard::~InterruptGuard() {
  std::signal(SIGINT, previous_int == SIG_ERR ? SIG_DFL : previous_int);
  std::signal(SIGTERM, previous_term == SIG_ERR ? SIG_DFL : previous_term);
}

const std::atomic<bool>& InterruptGuard::requested() const { return interrupt_flag; }
int InterruptGuard::signal_number() const { return interrupt_signal.load(); }

void request_interrupt(int signal_number) {
  interrupt_signal.store(signal_number);
  interrupt_flag.store(true);
}

}  // namespace granflow
