// bench scaling's serial and parallel parts from the loop thread's and the process's CPU time
// (scaling_benchmark.hpp): frames of known parts, as the threads would report them.
#include <gtest/gtest.h>

#include <stdexcept>

#include "holo/eval/scaling_benchmark.hpp"

namespace holo::eval {
namespace {

// What n threads report for a frame of serial work S and parallel work P split evenly: the
// loop's thread S + P / n, the process S + P.
struct Reported {
  double loop_thread_ms, process_ms;
};
Reported reported(double serial_ms, double parallel_ms, int threads) {
  return {serial_ms + parallel_ms / threads, serial_ms + parallel_ms};
}

TEST(ThreadParts, RecoversTheSerialAndParallelWorkOfAFrame) {
  for (const int threads : {2, 3, 8}) {
    const Reported r = reported(12.0, 90.0, threads);
    const ThreadParts parts = threadParts(threads, r.loop_thread_ms, r.process_ms);
    EXPECT_NEAR(parts.serial_ms, 12.0, 1e-9) << threads;
    EXPECT_NEAR(parts.parallel_ms, 90.0, 1e-9) << threads;
  }
}

TEST(ThreadParts, AFrameTheOtherThreadsNeverHelpIsAllSerial) {
  const ThreadParts parts = threadParts(2, 80.0, 80.0);
  EXPECT_DOUBLE_EQ(parts.serial_ms, 80.0);
  EXPECT_DOUBLE_EQ(parts.parallel_ms, 0.0);
  EXPECT_FALSE(parts.coresFor(33.3).has_value());  // no core count helps
}

TEST(ThreadParts, CoresForTheBudgetFollowAmdahl) {
  const ThreadParts parts{13.0, 100.0};
  // 13 + 100 / n <= 33.3 first at n = 5.
  EXPECT_EQ(parts.coresFor(33.3), 5);
  EXPECT_GT(parts.onCores(4), 33.3);
  EXPECT_LE(parts.onCores(5), 33.3);
  EXPECT_EQ((ThreadParts{5.0, 20.0}.coresFor(33.3)), 1);  // one core already fits
}

TEST(ThreadParts, OneThreadCannotTellThePartsApart) {
  EXPECT_THROW(threadParts(1, 50.0, 50.0), std::invalid_argument);
}

}  // namespace
}  // namespace holo::eval
