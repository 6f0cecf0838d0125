// tracers/parallel.cpp — parallel_for (see parallel.h).
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

bool parallel_for(std::size_t n, const ParallelOptions& options,
                  const std::function<void(std::size_t, std::size_t)>& body) {
    const std::size_t chunk = std::max<std::size_t>(1, options.chunk);
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> done{0};
    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::condition_variable finished_cv;
    unsigned finished = 0;
    std::exception_ptr error;
    auto cancelled = [&] {
        return options.cancel && options.cancel->load(std::memory_order_relaxed);
    };

    auto worker = [&] {
        NearestScope env;
        try {
            while (!stop.load(std::memory_order_relaxed) && !cancelled()) {
                const std::size_t begin = next.fetch_add(chunk, std::memory_order_relaxed);
                if (begin >= n) break;
                const std::size_t end = std::min(n, begin + chunk);
                body(begin, end);
                done.fetch_add(end - begin, std::memory_order_relaxed);
            }
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!error) error = std::current_exception();
            stop.store(true);
        }
        std::lock_guard lock(mutex);
        ++finished;
        finished_cv.notify_all();
    };

    const unsigned workers = static_cast<unsigned>(
        std::clamp<std::size_t>((n + chunk - 1) / chunk, 1, worker_count(options.threads)));
    if (workers == 1 && !options.progress) {
        worker();  // no thread to start
    } else {
        std::vector<std::thread> pool;
        pool.reserve(workers);
        for (unsigned i = 0; i < workers; ++i) pool.emplace_back(worker);
        {
            std::unique_lock lock(mutex);
            while (!finished_cv.wait_for(lock, options.progress_period,
                                         [&] { return finished == workers; })) {
                if (options.progress) {
                    lock.unlock();
                    options.progress(done.load(std::memory_order_relaxed), n);
                    lock.lock();
                }
            }
        }
        for (std::thread& t : pool) t.join();
    }
    if (error) std::rethrow_exception(error);
    if (cancelled() && done.load() < n) return false;
    if (options.progress) options.progress(n, n);
    return true;
}

}  // namespace certray::tracers
