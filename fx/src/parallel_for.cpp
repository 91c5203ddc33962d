// cellfx's own persistent thread pool behind fx::default_parallel_for().
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "fx/parallel_for.hpp"

namespace cellfx::fx {
namespace {

// Workers wait for a job; a job hands out indices from an atomic counter to the workers and
// the caller alike, so a slow thread never holds the others up. One job at a time: a second
// caller (another thread, or a task calling back in) runs its job inline instead of waiting.
class ThreadPool {
public:
    ThreadPool() : threads_(std::max(1u, std::thread::hardware_concurrency())) {}
    ~ThreadPool() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : workers_) t.join();
    }

    std::size_t threads() const { return threads_; }

    void run(std::size_t count, ParallelFor::Task task, void* context) {
        std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
        if (count <= 1 || threads_ <= 1 || !busy.owns_lock()) {
            for (std::size_t i = 0; i < count; ++i) task(context, i);
            return;
        }
        start_workers();
        Job job{task, context, count};
        {
            // A worker still inside the previous job (it found no index left) must leave it
            // before the counters are reset for this one.
            std::unique_lock<std::mutex> lock(mutex_);
            finished_.wait(lock, [&] { return active_ == 0; });
            job_ = job;
            next_.store(0), done_.store(0);
            ++generation_;
        }
        wake_.notify_all();
        work(job);
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [&] { return done_.load() == count && active_ == 0; });
    }

private:
    struct Job {
        ParallelFor::Task task = nullptr;
        void* context = nullptr;
        std::size_t count = 0;
    };

    void start_workers() { // once; with busy_ held
        if (!workers_.empty()) return;
        for (std::size_t i = 1; i < threads_; ++i) workers_.emplace_back([this] { worker(); });
    }

    void work(const Job& job) {
        for (std::size_t i = next_.fetch_add(1); i < job.count; i = next_.fetch_add(1)) {
            job.task(job.context, i);
            done_.fetch_add(1);
        }
    }

    void worker() {
        std::size_t seen = 0;
        for (;;) {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
            if (stopping_) return;
            seen = generation_;
            const Job job = job_; // the job of the generation just seen, read under the lock
            ++active_;
            lock.unlock();
            work(job);
            lock.lock();
            --active_;
            if (active_ == 0) finished_.notify_all();
        }
    }

    const std::size_t threads_;
    std::vector<std::thread> workers_;
    std::mutex busy_; // held by the caller whose job runs
    std::mutex mutex_;
    std::condition_variable wake_, finished_;
    bool stopping_ = false;
    std::size_t generation_ = 0, active_ = 0;
    Job job_;
    std::atomic<std::size_t> next_{0}, done_{0};
};

ThreadPool& pool() {
    static ThreadPool p;
    return p;
}

void run_on_pool(void* host, std::size_t count, ParallelFor::Task task, void* context) {
    static_cast<ThreadPool*>(host)->run(count, task, context);
}

} // namespace

ParallelFor default_parallel_for() {
    ParallelFor p;
    p.run = run_on_pool;
    p.host_context = &pool();
    return p;
}

std::size_t default_parallel_for_threads() { return pool().threads(); }

} // namespace cellfx::fx
