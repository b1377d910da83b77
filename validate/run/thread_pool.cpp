#include "validate/run/thread_pool.h"

#include <exception>

namespace warpcheck {

namespace {
thread_local const void* t_current_tag = nullptr;
}  // namespace

const void* ThreadPool::current_tag() { return t_current_tag; }
void ThreadPool::set_current_tag(const void* tag) { t_current_tag = tag; }

// One parallel_for call. Indices are handed out through `next`; `finished`
// counts completed calls so the owner knows when the loop is over.
struct ThreadPool::Loop {
    std::size_t n = 0;
    const std::function<void(std::size_t)>* body = nullptr;
    const void* tag = nullptr;  // the starting thread's current_tag()
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> finished{0};
    std::mutex error_mutex;
    std::exception_ptr error;
    std::condition_variable done;
    std::mutex done_mutex;
};

ThreadPool::ThreadPool(unsigned threads) {
    const unsigned extra = threads > 1 ? threads - 1 : 0;
    workers_.reserve(extra);
    for (unsigned i = 0; i < extra; ++i) workers_.emplace_back([this] { worker_main(); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
}

// Runs one index of `loop` if any is left; returns false when none was.
bool ThreadPool::run_one(Loop& loop) {
    const std::size_t i = loop.next.fetch_add(1, std::memory_order_relaxed);
    if (i >= loop.n) return false;
    bool skip = false;
    {
        std::lock_guard lock(loop.error_mutex);
        skip = loop.error != nullptr;
    }
    if (!skip) {
        const void* own_tag = t_current_tag;
        t_current_tag = loop.tag;
        try {
            (*loop.body)(i);
        } catch (...) {
            std::lock_guard lock(loop.error_mutex);
            if (!loop.error) loop.error = std::current_exception();
        }
        t_current_tag = own_tag;
    }
    if (loop.finished.fetch_add(1, std::memory_order_acq_rel) + 1 == loop.n) {
        std::lock_guard lock(loop.done_mutex);
        loop.done.notify_all();
    }
    return true;
}

void ThreadPool::worker_main() {
    for (;;) {
        std::shared_ptr<Loop> loop;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stopping_ || !loops_.empty(); });
            if (stopping_ && loops_.empty()) return;
            loop = loops_.front();
            // A loop whose indices are all handed out leaves the queue; the
            // threads still running its last indices finish them on their own.
            if (loop->next.load(std::memory_order_relaxed) >= loop->n) {
                loops_.pop_front();
                continue;
            }
        }
        run_one(*loop);
    }
}

void ThreadPool::parallel_for(std::size_t n, const std::function<void(std::size_t)>& body) {
    if (n == 0) return;
    if (workers_.empty() || n == 1) {
        for (std::size_t i = 0; i < n; ++i) body(i);
        return;
    }
    auto loop = std::make_shared<Loop>();
    loop->n = n;
    loop->body = &body;
    loop->tag = t_current_tag;
    {
        std::lock_guard lock(mutex_);
        loops_.push_back(loop);
    }
    wake_.notify_all();
    while (run_one(*loop)) {
    }
    {
        std::unique_lock lock(loop->done_mutex);
        loop->done.wait(lock, [&] { return loop->finished.load(std::memory_order_acquire) == loop->n; });
    }
    {
        std::lock_guard lock(mutex_);
        std::erase(loops_, loop);
    }
    if (loop->error) std::rethrow_exception(loop->error);
}

}  // namespace warpcheck
