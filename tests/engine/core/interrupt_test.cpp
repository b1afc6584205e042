// SIGINT and SIGTERM set a flag the run polls; the previous handlers come
// back when the guard goes.

#include "engine/core/interrupt.hpp"

#include <gtest/gtest.h>

#include <csignal>

namespace granflow {
namespace {

void (*current_handler(int signal_number))(int) {
  struct sigaction now {};
  sigaction(signal_number, nullptr, &now);
  return now.sa_handler;
}

TEST(Interrupt, ASignalIsRecordedInsteadOfEndingTheProcess) {
  InterruptGuard guard;
  EXPECT_FALSE(guard.requested());
  EXPECT_EQ(guard.signal_number(), 0);
  ASSERT_EQ(std::raise(SIGTERM), 0);  // would end the test without the guard
  EXPECT_TRUE(guard.requested());
  EXPECT_EQ(guard.signal_number(), SIGTERM);
}

TEST(Interrupt, ARequestActsAsTheSignal) {
  InterruptGuard guard;
  request_interrupt(SIGINT);
  EXPECT_TRUE(guard.requested());
  EXPECT_EQ(guard.signal_number(), SIGINT);
}

TEST(Interrupt, TheGuardRestoresThePreviousHandlers) {
  const auto before_int = current_handler(SIGINT), before_term = current_handler(SIGTERM);
  {
    InterruptGuard guard;
    EXPECT_NE(current_handler(SIGINT), before_int);
    EXPECT_NE(current_handler(SIGTERM), before_term);
  }
  EXPECT_EQ(current_handler(SIGINT), before_int);
  EXPECT_EQ(current_handler(SIGTERM), before_term);
}

}  // namespace
}  // namespace granflow
