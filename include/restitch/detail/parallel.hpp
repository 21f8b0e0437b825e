// restitch/detail/parallel.hpp - a deterministic task loop on a few threads.
//
// The analysis' heavy stages (descriptors, matching, offset refinement) are
// loops over independent tasks. `parallel_tasks(threads, tasks, body, tick)`
// runs body(task, worker) for every task in [0, tasks) on `threads` workers:
// the calling thread is worker 0, the others are std::threads started here
// and joined before it returns. Tasks are handed out in increasing order from
// a shared counter (so long tasks put first balance well). Which worker runs
// which task depends on timing; callers make the result independent of it
// (each task writes its own rows, or each worker its own state, merged after
// in worker-independent order). That is what makes every result
// bit-identical whatever the thread count ("[threads]" tests in
// tests/analyze_test.cpp, matcher_test.cpp and runtime_test.cpp).
//
// Progress and cancel: only worker 0 calls tick(done) (done: tasks finished
// so far, all workers), after each of its tasks, and once more with
// done = tasks after the join if its last tick was not that one, so a
// Progress callback (which may call into JavaScript) is only ever called
// from the calling thread, at least once per call, with done increasing.
// tick returning false stops every worker before its next task and
// parallel_tasks returns false. An exception thrown by a task stops the
// workers too and is rethrown here after the join (the callers' `guarded`
// turns it into a Status).
//
// threads <= 1, or a single task, runs inline: no thread is created. A
// WebAssembly build without pthreads (the page's module) always runs
// inline. A thread that cannot be started (std::system_error) is simply not
// used: its share of the tasks goes to the workers that run.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace restitch {

/// The number of workers a `threads` option asks for: 0 means every hardware thread (at least 1).
template <class = void>
int resolve_threads(int threads) {
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
  (void)threads;
  return 1;  // built without threads (the page's module): every loop runs on the calling thread
#else
  if (threads > 0) return threads;
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : int(n);
#endif
}

namespace detail {

/// Sets a policy's worker count where it has one (AnalysisOptions::threads, RetargetOptions::threads); a
/// policy without does what it always does.
template <class P>
auto set_policy_threads(P& p, int n, int) -> decltype(p.threads = n, void()) {
  p.threads = n;
}
template <class P>
auto set_policy_threads(P& p, int n, long) -> decltype(p.significance.threads = n, void()) {
  p.significance.threads = n;
}
template <class P>
void set_policy_threads(P&, int, ...) {}

/// Runs body(task, worker) for task in [0, tasks) on min(threads, tasks) workers (see the header
/// comment). Returns false when tick returned false (the run was stopped), true otherwise.
template <class Body, class Tick>
bool parallel_tasks(int threads, std::size_t tasks, Body&& body, Tick&& tick) {
  const int workers =
      int(std::min<std::size_t>(std::size_t(resolve_threads(std::max(1, threads))), std::max<std::size_t>(tasks, 1)));
  if (workers <= 1) {
    for (std::size_t t = 0; t < tasks; ++t) {
      body(t, 0);
      if (!tick(t + 1)) return false;
    }
    return true;
  }
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> stop{false}, cancelled{false};
  std::size_t last_tick = 0;  // worker 0's last tick (worker 0 alone writes it)
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto run = [&](int worker) {
    for (;;) {
      if (stop.load(std::memory_order_relaxed)) return;
      const std::size_t t = next.fetch_add(1);
      if (t >= tasks) return;
      try {
        body(t, worker);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        stop = true;
        return;
      }
      const std::size_t finished = done.fetch_add(1) + 1;
      if (worker == 0 && !tick(last_tick = finished)) cancelled = true, stop = true;
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w) {
    try {
      pool.emplace_back(run, w);
    } catch (const std::system_error&) {
      break;  // no more threads: the workers that run take every task
    }
  }
  run(0);
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  // The other workers may have run the last tasks: one last tick, so a cancel is always seen.
  if (!cancelled.load() && last_tick != tasks && !tick(tasks)) return false;
  return !cancelled.load();
}

}  // namespace detail
}  // namespace restitch
