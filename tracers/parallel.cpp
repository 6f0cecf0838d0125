// tracers/parallel.cpp — run_workers and parallel_for (see parallel.h).
#include "tracers/parallel.h"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "interval/interval.h"

namespace certray::tracers {

unsigned worker_count(unsigned threads) {
    return threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
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
    std::vector<std::thread> pool;
    const unsigned first_thread = poll ? 0 : 1;
    pool.reserve(workers);
    for (unsigned k = first_thread; k < workers; ++k) pool.emplace_back(run, k);
    if (!poll) {
        run(0);
    } else {
        std::unique_lock lock(mutex);
        while (!finished_cv.wait_for(lock, period, [&] { return finished == workers; })) {
            lock.unlock();
            poll();
            lock.lock();
        }
    }
    for (std::thread& t : pool) t.join();
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
