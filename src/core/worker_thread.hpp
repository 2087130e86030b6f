// One long-lived thread that runs posted jobs one at a time: the window's pipeline, and the
// second half of the visibility stages that split their work in two. A new std::thread per job
// costs its creation (measured: bench/results/model.md) and starts its thread_local working
// storage empty (allocated, and its pages faulted in, again); this thread keeps both, so that
// work split in two costs only the hand-over.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <memory>
#include <utility>
#include <vector>

namespace inkline {

class WorkerThread {
public:
    WorkerThread() : thread_([this] { run(); }) {}
    ~WorkerThread() {  // (after the job in flight, if any)
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_one();
        thread_.join();
    }
    WorkerThread(const WorkerThread&) = delete;
    WorkerThread& operator=(const WorkerThread&) = delete;

    // Runs fn on the thread; the caller waits for the returned future before posting again. A
    // job's exception reaches its future, as with std::async.
    std::future<void> post(std::function<void()> fn) {
        std::packaged_task<void()> task(std::move(fn));
        std::future<void> done = task.get_future();
        {
            std::lock_guard<std::mutex> lock(mutex_);
            task_ = std::move(task);
        }
        wake_.notify_one();
        return done;
    }

    // Runs `there` on the thread and `here` on the caller's, and returns once both are done (so
    // both may use the caller's locals); an exception of either is rethrown then, here's first.
    template <class Here>
    void fork_join(std::function<void()> there, Here&& here) {
        std::future<void> done = post(std::move(there));
        try {
            here();
        } catch (...) {
            done.wait();
            throw;
        }
        done.get();
    }

private:
    void run() {
        for (;;) {
            std::packaged_task<void()> task;
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [&] { return stop_ || task_.valid(); });
                if (!task_.valid()) return;  // stopped, nothing left to run
                task = std::move(task_);
            }
            task();
        }
    }
    std::mutex mutex_;
    std::condition_variable wake_;
    std::packaged_task<void()> task_;  // the job posted, not yet started
    bool stop_ = false;
    std::thread thread_;  // (last: started once the members above exist)
};

// A frame's threads for stages split in k parts: k - 1 long-lived WorkerThreads (made on first
// need, kept) and the calling thread. Part i's result is the caller's to merge in part order, so
// the outcome does not depend on which thread ran which part, nor on the thread count.
class WorkerTeam {
public:
    // Runs part(i) for i in [0, parts): part 0 on the calling thread, part i on worker i - 1.
    // Returns once every part is done; the first part's exception (in part order) is rethrown.
    template <class Part>
    void run(int parts, Part&& part) {
        if (parts <= 1) {
            if (parts == 1) part(0);
            return;
        }
        while (int(workers_.size()) < parts - 1) workers_.push_back(std::make_unique<WorkerThread>());
        std::vector<std::future<void>> done;
        done.reserve(std::size_t(parts - 1));
        for (int i = 1; i < parts; ++i) done.push_back(workers_[std::size_t(i - 1)]->post([&part, i] { part(i); }));
        std::exception_ptr first;
        try {
            part(0);
        } catch (...) {
            first = std::current_exception();
        }
        for (auto& d : done) {
            try {
                d.get();
            } catch (...) {
                if (!first) first = std::current_exception();
            }
        }
        if (first) std::rethrow_exception(first);
    }
    // The first worker (made on first need): a stage split in two runs its second half there.
    WorkerThread& first_worker() {
        if (workers_.empty()) workers_.push_back(std::make_unique<WorkerThread>());
        return *workers_.front();
    }

private:
    std::vector<std::unique_ptr<WorkerThread>> workers_;
};

}  // namespace inkline
