// tracers/parallel.cpp — run_workers and parallel_for (see parallel.h).
#include "tracers/parallel.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "interval/interval.h"

namespace certray::tracers {

unsigned worker_count(unsigned threads) {
    return threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
}

namespace {

/// How long an idle pool thread spins (watching for work, its core awake) before it sleeps. A
/// sleeping thread's core may take milliseconds to wake on a virtual machine: measured on the
/// development machine, the second worker of a 35 ms render started up to 3.6 ms late
/// (docs/benchmarks.md, session 29).
constexpr auto kSpin = std::chrono::milliseconds(30);
/// More threads than this are not kept: a run that asks for more starts its own.
constexpr unsigned kMostPooled = 256;

void pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
}

/// The threads kept between runs (tracers/parallel.h's contract). One run at a time: a run that
/// finds the pool busy (another thread's run, or one nested in a worker) starts its own threads.
/// Never destroyed (its threads outlive main's return harmlessly: idle, they touch only the
/// pool), and made anew in a child process after fork (which has none of its parent's threads).
class Pool {
  public:
    static Pool& get() {
        static std::mutex made;
        static Pool* pool = nullptr;
        static pid_t owner = 0;
        std::lock_guard lock(made);
        if (pool == nullptr || owner != getpid()) {
            pool = new Pool();  // a parent's pool is left as it is: its threads are not ours
            owner = getpid();
        }
        return *pool;
    }

    /// Grows the pool to `threads` threads (at most kMostPooled), each spinning for kSpin first.
    /// A thread that cannot be started (std::system_error) leaves the pool smaller: a run starts
    /// what it lacks then.
    void reserve(unsigned threads) {
        std::lock_guard lock(mutex_);
        try {
            grow(std::min(threads, kMostPooled));
        } catch (const std::system_error&) {
        }
    }

    /// Starts run(k) for k in [first, workers) on the pool's threads (run catches its own
    /// exceptions, and must outlive the run); wait() returns when all have returned. False, with
    /// nothing started, where the pool is busy or would be too large.
    bool start(unsigned first, unsigned workers, const std::function<void(unsigned)>& run) {
        const unsigned needed = workers - first;
        {
            std::lock_guard lock(mutex_);
            if (busy_ || needed > kMostPooled) return false;
            grow(needed);  // may throw (no thread to be had): then nothing has changed
            busy_ = true;
            job_ = &run;
            next_ = first;
            end_ = workers;
            needed_ = needed;
            remaining_ = needed;
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        return true;
    }
    void wait() {
        std::unique_lock lock(mutex_);
        done_.wait(lock, [&] { return remaining_ == 0; });
        job_ = nullptr;
        busy_ = false;
    }

  private:
    Pool() = default;

    void grow(unsigned threads) {  // under mutex_
        for (; size_ < threads; ++size_) {
            // It starts idle at the current run count: the run being set up is new to it.
            const std::uint64_t seen = generation_.load(std::memory_order_relaxed);
            std::thread([this, index = size_, seen] { loop(index, seen); }).detach();
        }
    }

    void loop(unsigned index, std::uint64_t seen) {
        bool spin = true;  // after its start and after work; not after a run that left it out
        for (;;) {
            // Idle: spin while kSpin lasts, then sleep until the next run.
            const auto until = std::chrono::steady_clock::now() + kSpin;
            for (unsigned n = 1; spin && generation_.load(std::memory_order_acquire) == seen; ++n) {
                pause();
                if (n % 64 == 0 && std::chrono::steady_clock::now() > until) break;
            }
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return generation_.load(std::memory_order_relaxed) != seen; });
            seen = generation_.load(std::memory_order_relaxed);
            // A thread the run does not need (index ≥ needed_) goes back to sleep; the others
            // take the run's indices one at a time while any are left.
            spin = job_ != nullptr && index < needed_;
            while (job_ != nullptr && index < needed_ && next_ < end_) {
                const unsigned k = next_++;
                const std::function<void(unsigned)>& job = *job_;
                lock.unlock();
                job(k);
                lock.lock();
                if (--remaining_ == 0) done_.notify_all();
            }
        }
    }

    std::mutex mutex_;
    std::condition_variable wake_, done_;
    unsigned size_ = 0;  ///< threads started (detached: the pool is never destroyed)
    std::atomic<std::uint64_t> generation_{0};  ///< one more at each run's start
    bool busy_ = false;
    const std::function<void(unsigned)>* job_ = nullptr;
    unsigned next_ = 0, end_ = 0, needed_ = 0, remaining_ = 0;
};

}  // namespace

void prestart_workers(unsigned threads) {
    const unsigned workers = worker_count(threads);
    if (workers > 1) Pool::get().reserve(workers - 1);
}

void run_workers(unsigned workers, const std::function<void(unsigned)>& fn,
                 const std::function<void()>& poll, std::chrono::milliseconds period) {
    workers = std::max(1u, workers);
    std::mutex mutex;
    std::condition_variable finished_cv;
    unsigned finished = 0;
    std::exception_ptr error;
    auto run = [&](unsigned k) {
        NearestScope env;
        try {
            fn(k);
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!error) error = std::current_exception();
        }
        std::lock_guard lock(mutex);
        ++finished;
        finished_cv.notify_all();
    };
    const unsigned first_thread = poll ? 0 : 1;
    // On the calling thread: worker 0, or the polling until every worker has returned.
    const auto caller = [&] {
        if (!poll) {
            run(0);
            return;
        }
        std::unique_lock lock(mutex);
        while (!finished_cv.wait_for(lock, period, [&] { return finished == workers; })) {
            lock.unlock();
            poll();
            lock.lock();
        }
    };
    // The other workers on the pool's threads, or (the pool busy: a run on another thread, or
    // this one nested in a worker) on threads of this run's own; those that no thread can be had
    // for (std::system_error), here, before the caller's part (fn waits for no other k).
    std::function<void(unsigned)> job;  // the pool holds its address until wait()
    bool pooled = false;
    unsigned started = first_thread;  // workers [first_thread, started) are on threads
    if (first_thread < workers) {
        job = run;
        try {
            pooled = Pool::get().start(first_thread, workers, job);
        } catch (const std::system_error&) {
        }
        if (pooled) started = workers;
    }
    std::vector<std::thread> own;
    if (!pooled) {
        own.reserve(workers);
        try {
            for (; started < workers; ++started) own.emplace_back(run, started);
        } catch (const std::system_error&) {
        }
    }
    for (unsigned k = started; k < workers; ++k) run(k);
    // The workers refer to this frame: they are waited for even where the poll throws (a progress
    // callback may), whose exception comes after them.
    std::exception_ptr thrown;
    try {
        caller();
    } catch (...) {
        thrown = std::current_exception();
    }
    if (pooled) Pool::get().wait();
    for (std::thread& t : own) t.join();
    if (thrown) std::rethrow_exception(thrown);
    if (error) std::rethrow_exception(error);
}

bool parallel_for(std::size_t n, const ParallelOptions& options,
                  const std::function<void(std::size_t, std::size_t, unsigned)>& body) {
    const std::size_t chunk = std::max<std::size_t>(1, options.chunk);
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> done{0};
    std::atomic<bool> stop{false};
    auto cancelled = [&] {
        return options.cancel && options.cancel->load(std::memory_order_relaxed);
    };
    const unsigned workers = static_cast<unsigned>(
        std::clamp<std::size_t>((n + chunk - 1) / chunk, 1, worker_count(options.threads)));
    std::function<void()> poll;
    if (options.progress) poll = [&] { options.progress(done.load(std::memory_order_relaxed), n); };
    run_workers(
        workers,
        [&](unsigned k) {
            try {
                while (!stop.load(std::memory_order_relaxed) && !cancelled()) {
                    const std::size_t begin = next.fetch_add(chunk, std::memory_order_relaxed);
                    if (begin >= n) break;
                    const std::size_t end = std::min(n, begin + chunk);
                    body(begin, end, k);
                    done.fetch_add(end - begin, std::memory_order_relaxed);
                }
            } catch (...) {
                stop.store(true);
                throw;
            }
        },
        poll, options.progress_period);
    if (cancelled() && done.load() < n) return false;
    if (options.progress) options.progress(n, n);
    return true;
}

}  // namespace certray::tracers
